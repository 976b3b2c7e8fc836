//! The variable list of each FMU, declared once (the get/set code and the model description are
//! both generated from it).

use super::*;

const SPH: [(&str, &str, &str); 6] = [
    ("r", "m", "radius"),
    ("lon", "rad", "longitude"),
    ("lat", "rad", "latitude"),
    ("v", "m/s", "planet-relative speed"),
    ("fpa", "rad", "flight-path angle"),
    ("heading", "rad", "heading (north-clockwise)"),
];

struct Builder {
    vars: Vec<Var>,
}

impl Builder {
    #[allow(clippy::too_many_arguments)]
    fn add(
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
            (_, Type::Real) if !matches!(key, Key::MeasTime | Key::Meas(_)) => {
                Variability::Continuous
            }
            _ => Variability::Discrete,
        };
        self.vars.push(Var {
            vr: self.vars.len() as u32,
            name: name.into(),
            ty,
            causality,
            variability,
            unit,
            start,
            description: description.into(),
            key,
        });
    }

    fn out(
        &mut self,
        name: impl Into<String>,
        ty: Type,
        unit: Option<&'static str>,
        description: impl Into<String>,
        key: Key,
    ) {
        self.add(name, ty, Causality::Output, unit, None, description, key);
    }
}

/// The variables of `model`, in value-reference order.
pub fn variables(model: Model) -> Vec<Var> {
    use Causality::*;
    use Type::*;
    let mut b = Builder { vars: Vec::new() };
    b.add(
        "scenario",
        String,
        Parameter,
        None,
        Some(Value::String(DEFAULT_SCENARIO.into())),
        format!(
            "Scenario: a built-in name ({}) or a TOML file in the FMU's resources folder (or an absolute path)",
            entrynav::scenario::BUILTIN_NAMES.join(", ")
        ),
        Key::Scenario,
    );
    if model.has_filter() {
        b.add(
            "filter",
            String,
            Parameter,
            None,
            Some(Value::String(DEFAULT_FILTER.into())),
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
    // Every model: the truth flies the command, the filter's onboard models use it (known onboard).
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
            Model::Truth => "Bank-angle command, held over each communication step",
        },
        Key::Bank,
    );
    if model.has_truth() {
        for i in 0..MAX_BEACONS {
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
    if model != Model::Combined {
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
        for (k, (n, u, d)) in SPH.iter().enumerate() {
            b.out(
                format!("truth_{n}"),
                Real,
                Some(u),
                format!("True {d} (planet-relative spherical)"),
                Key::TruthSph(k),
            );
        }
        b.out(
            "truth_altitude",
            Real,
            Some("m"),
            "True altitude",
            Key::TruthAltitude,
        );
        b.out(
            "truth_density",
            Real,
            Some("kg/m3"),
            "True atmospheric density",
            Key::TruthDensity,
        );
        b.out(
            "truth_dynamic_pressure",
            Real,
            Some("Pa"),
            "True dynamic pressure",
            Key::TruthDynamicPressure,
        );
        b.out(
            "truth_heating",
            Real,
            Some("W/m2"),
            "True convective heating rate (Sutton-Graves)",
            Key::TruthHeating,
        );
        b.out(
            "truth_aero_accel",
            Real,
            Some("m/s2"),
            "Magnitude of the aerodynamic acceleration",
            Key::TruthAeroAccel,
        );
        for k in 0..3 {
            b.out(
                format!("truth_sensed_accel_{}", ["x", "y", "z"][k]),
                Real,
                Some("m/s2"),
                format!(
                    "Noiseless sensed acceleration (specific force), IMU axis {}",
                    ["x", "y", "z"][k]
                ),
                Key::TruthSensedAccel(k),
            );
        }
        for i in 0..MAX_BEACONS {
            b.out(
                format!("beacon_range_{}", i + 1),
                Real,
                Some("m"),
                format!("Geometric range to beacon {}", i + 1),
                Key::BeaconRange(i),
            );
            b.out(
                format!("beacon_visible_{}", i + 1),
                Boolean,
                None,
                format!("Beacon {} is above the horizon", i + 1),
                Key::BeaconVisible(i),
            );
        }
        b.out(
            "truth_stop",
            Integer,
            None,
            "0 running, 1 scenario duration reached, 2 stop speed reached, 3 ground reached",
            Key::TruthStop,
        );
        b.out(
            "n_beacons",
            Integer,
            None,
            "Number of beacons of the scenario",
            Key::NBeacons,
        );
    }
    if model.has_filter() {
        b.out(
            "nav_time",
            Real,
            Some("s"),
            "Epoch of the estimate (the last measurement epoch processed; 0 before the first)",
            Key::NavTime,
        );
        b.out(
            "nav_status",
            Integer,
            None,
            "Filter status: 0 not started, 1 running, 2 failed (estimate frozen, reason logged)",
            Key::NavStatus,
        );
        b.out(
            "n_states",
            Integer,
            None,
            "Filter state dimension N (slots past N read 0)",
            Key::NStates,
        );
        for i in 0..MAX_STATES {
            b.out(
                format!("est_x_{}", i + 1),
                Real,
                None,
                format!("Estimate, filter state {} (filter-model coordinates: r lon lat v fpa heading or x y z vx vy vz, then augmented states)", i + 1),
                Key::EstX(i),
            );
        }
        for i in 0..MAX_STATES {
            b.out(
                format!("est_sigma_{}", i + 1),
                Real,
                None,
                format!("1-sigma of filter state {}", i + 1),
                Key::EstSigma(i),
            );
        }
        for (k, (n, u, d)) in SPH.iter().enumerate() {
            b.out(
                format!("est_{n}"),
                Real,
                Some(u),
                format!("Estimated {d} (planet-relative spherical)"),
                Key::EstSph(k),
            );
        }
        b.out(
            "est_density",
            Real,
            Some("kg/m3"),
            "Filter's density estimate (NaN when the filter does not estimate density)",
            Key::EstDensity,
        );
        b.out(
            "nis",
            Real,
            None,
            "Normalised innovation squared of the last update (NaN when no measurement was used)",
            Key::Nis,
        );
        b.out(
            "n_meas",
            Integer,
            None,
            "Scalar measurements used in the last update",
            Key::NMeas,
        );
        for i in 0..MAX_WEIGHTS {
            b.out(
                format!("weight_{}", i + 1),
                Real,
                None,
                format!(
                    "Fusion weight (ci, dcifaif) or model probability (mmae, mmae-moe) {}",
                    i + 1
                ),
                Key::Weight(i),
            );
        }
        b.out(
            "n_weights",
            Integer,
            None,
            "Number of fusion weights / model probabilities (0 for ekf and ukf)",
            Key::NWeights,
        );
    }
    if model == Model::Combined {
        for i in 0..MAX_STATES {
            b.out(
                format!("truth_x_{}", i + 1),
                Real,
                None,
                format!(
                    "Truth of filter state {} at the estimate's epoch (NaN without a truth counterpart)",
                    i + 1
                ),
                Key::TruthX(i),
            );
        }
        for i in 0..MAX_STATES {
            b.out(
                format!("err_{}", i + 1),
                Real,
                None,
                format!(
                    "Estimation error est_x - truth_x of filter state {} (angles wrapped)",
                    i + 1
                ),
                Key::Err(i),
            );
        }
        b.out(
            "nees",
            Real,
            None,
            "Normalised estimation error squared over the states with a truth value",
            Key::Nees,
        );
        b.out(
            "nees_dof",
            Integer,
            None,
            "Degrees of freedom of the NEES",
            Key::NeesDof,
        );
        b.out(
            "nav_truth_density",
            Real,
            Some("kg/m3"),
            "True density at the estimate's epoch",
            Key::NavTruthDensity,
        );
    }
    b.vars
}
