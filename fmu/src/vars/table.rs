//! The variable list of each FMU, declared once (the get/set code and the model description are
//! both generated from it).

use super::table_outputs::{judgement_outputs, nav_outputs, truth_outputs};
use super::*;

pub(super) const SPH: [(&str, &str, &str); 6] = [
    ("r", "m", "radius"),
    ("lon", "rad", "longitude"),
    ("lat", "rad", "latitude"),
    ("v", "m/s", "planet-relative speed"),
    ("fpa", "rad", "flight-path angle"),
    ("heading", "rad", "heading (north-clockwise)"),
];

pub(crate) struct Builder {
    pub(super) vars: Vec<Var>,
}

/// Reals of the sampled-data part (measurements, the estimate and its judgement) change only at
/// measurement epochs; the truth and the bank command are continuous.
fn real_variability(key: Key) -> Variability {
    match key {
        Key::Bank
        | Key::TruthSph(_)
        | Key::TruthAltitude
        | Key::TruthDensity
        | Key::TruthDynamicPressure
        | Key::TruthHeating
        | Key::TruthAeroAccel
        | Key::TruthSensedAccel(_)
        | Key::BeaconRange(_) => Variability::Continuous,
        _ => Variability::Discrete,
    }
}

impl Builder {
    #[allow(clippy::too_many_arguments)]
    pub(super) fn add(
        &mut self,
        name: impl Into<String>,
        ty: Type,
        causality: Causality,
        unit: Option<&'static str>,
        start: Option<Value>,
        description: impl Into<String>,
        key: Key,
    ) {
        let variability = match (causality, ty) {
            (Causality::Parameter, _) => Variability::Fixed,
            (_, Type::Real) => real_variability(key),
            _ => Variability::Discrete,
        };
        self.vars.push(Var {
            vr: self.vars.len() as u32,
            name: name.into(),
            ty,
            declared: None,
            causality,
            variability,
            unit,
            start,
            description: description.into(),
            key,
        });
    }

    pub(super) fn out(
        &mut self,
        name: impl Into<String>,
        ty: Type,
        unit: Option<&'static str>,
        description: impl Into<String>,
        key: Key,
    ) {
        self.add(name, ty, Causality::Output, unit, None, description, key);
    }

    /// An Integer output declared as the Enumeration `e`.
    pub(super) fn enumeration(
        &mut self,
        name: &str,
        e: &'static EnumType,
        description: &str,
        key: Key,
    ) {
        self.out(name, Type::Integer, None, description, key);
        if let Some(v) = self.vars.last_mut() {
            v.declared = Some(e);
        }
    }
}

/// The variables of the generic `model`, in value-reference order.
pub fn variables(model: Model) -> Vec<Var> {
    build(model, None)
}

/// The variables of `model`, generic or specific to an embedded scenario.
pub(super) fn build(model: Model, specific: Option<&Specific>) -> Vec<Var> {
    use Causality::*;
    use Type::*;
    let mut b = Builder { vars: Vec::new() };
    if model == Model::Guidance {
        super::table_guidance::guided_scenario_param(&mut b);
        super::table_guidance::guidance_vars(&mut b);
        return b.vars;
    }
    if model == Model::Guided {
        super::table_guidance::guided_scenario_param(&mut b);
    } else if specific.is_none() {
        b.add(
            "scenario",
            String,
            Parameter,
            None,
            Some(Value::String(DEFAULT_SCENARIO.into())),
            format!(
                "Scenario: a built-in name ({}) or a TOML file in the FMU's resources folder (a file elsewhere only with allow_external_files = true)",
                entrynav::scenario::BUILTIN_NAMES.join(", ")
            ),
            Key::Scenario,
        );
    }
    // The guided FMU's default scenario (msl-guided) has no radio beacons: the EKF, as in the
    // guided SSP's filter.
    let default_filter = match (specific, model) {
        (Some(s), _) => s.filter.name(),
        (None, Model::Guided) => GUIDED_FILTER,
        (None, _) => DEFAULT_FILTER,
    };
    if model.has_filter() {
        b.add(
            "filter",
            String,
            Parameter,
            None,
            Some(Value::String(default_filter.into())),
            format!(
                "Navigation filter, as entrynav trade: {}",
                entrynav::estimation::nav::FilterKind::ALL
                    .map(|k| k.name())
                    .join(", ")
            ),
            Key::Filter,
        );
    }
    b.add(
        "seed",
        Integer,
        Parameter,
        None,
        Some(Value::Integer(DEFAULT_SEED)),
        "Seed (>= 0) of the dispersions, measurement noise and filter start, as entrynav simulate --seed",
        Key::Seed,
    );
    b.add(
        "dispersed",
        Boolean,
        Parameter,
        None,
        Some(Value::Boolean(false)),
        "Draw the truth from the scenario's dispersions (true) or use the nominal truth (false)",
        Key::Dispersed,
    );
    if model == Model::Guided {
        b.add(
            "run",
            Integer,
            Parameter,
            None,
            Some(Value::Integer(0)),
            "With dispersed = true: the Monte Carlo run (0 to 999999999) whose truth, noise and filter start are flown, as run `run` of entrynav guidance deliver --seed seed (the same delivery, bit for bit); not used when dispersed = false",
            Key::Run,
        );
    }
    if specific.is_none() {
        b.add(
            "allow_external_files",
            Boolean,
            Parameter,
            None,
            Some(Value::Boolean(false)),
            "Let scenario name a file outside the FMU's resources folder (an absolute path or one with ..); off by default, so a parameter cannot make the FMU read host files",
            Key::AllowExternalFiles,
        );
    }
    let n_beacons = specific
        .map(|s| s.scenario.beacons.len().min(MAX_BEACONS))
        .unwrap_or(MAX_BEACONS);
    // Every model but the guided one (whose guidance commands the bank): the truth flies the
    // command, the filter's onboard models use it (known onboard).
    if model != Model::Guided {
        b.add(
        "bank_angle",
        Real,
        Input,
        Some("rad"),
        Some(Value::Real(0.0)),
        match model {
            Model::Combined => {
                "Bank-angle command, held over each communication step: flown by the truth and used by the filter's onboard dynamics and measurement models"
            }
            Model::Filter => {
                "Bank-angle command the vehicle flies, held over each communication step: used by the filter's onboard dynamics and measurement models"
            }
            Model::Truth | Model::Guidance | Model::Guided => {
                "Bank-angle command, held over each communication step"
            }
        },
        Key::Bank,
    );
    }
    if model.has_truth() {
        for i in 0..n_beacons {
            b.add(
                format!("beacon_available_{}", i + 1),
                Boolean,
                Input,
                None,
                Some(Value::Boolean(true)),
                format!(
                    "Beacon {} transmits (false: an outage commanded by the master)",
                    i + 1
                ),
                Key::BeaconAvailable(i),
            );
        }
    }
    // Measurements: inputs of the filter FMU, outputs of the truth FMU.
    if !model.is_closed() {
        let c = if model == Model::Filter {
            Input
        } else {
            Output
        };
        let start = |v: Value| (c == Input).then_some(v);
        b.add(
            "meas_epoch",
            Boolean,
            c,
            None,
            start(Value::Boolean(false)),
            "A measurement epoch: the meas_* values were taken at meas_time",
            Key::MeasEpoch,
        );
        b.add(
            "meas_time",
            Real,
            c,
            Some("s"),
            start(Value::Real(0.0)),
            "Time the measurements were taken",
            Key::MeasTime,
        );
        for s in Slot::all() {
            b.add(
                s.name(),
                Real,
                c,
                Some(s.unit()),
                start(Value::Real(0.0)),
                format!("Measured {} (0 when not valid)", s.what()),
                Key::Meas(s),
            );
            b.add(
                format!("{}_valid", s.name()),
                Boolean,
                c,
                None,
                start(Value::Boolean(false)),
                format!("The measured {} is valid at this epoch", s.what()),
                Key::MeasValid(s),
            );
        }
    }
    if model.has_truth() {
        truth_outputs(&mut b, n_beacons);
    }
    if model.has_filter() {
        nav_outputs(&mut b, specific);
    }
    if model.is_closed() {
        judgement_outputs(&mut b, specific);
    }
    if model == Model::Guided {
        super::table_guidance::guided_outputs(&mut b);
    }
    b.vars
}
