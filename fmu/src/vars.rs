//! The variable table: one list per FMU, used by the get/set code and by the `modelDescription.xml`
//! generator, so the two cannot disagree. The GUID is a hash of the table.
//!
//! The layout is fixed whatever the scenario: filter states in slots 1..=10 (slots past the
//! scenario's state dimension read 0), beacons in slots 1..=6 (past the scenario's beacon count:
//! 0 / false), fusion weights or model probabilities in slots 1..=8. Values that exist but are not
//! known read NaN (the truth of ρ0 when the truth atmosphere is not exponential, the NEES before it
//! is defined, the density estimate of a filter that does not estimate density).

use entrynav::sensors::Channel;

/// Filter state slots.
pub const MAX_STATES: usize = 10;
/// Beacon slots.
pub const MAX_BEACONS: usize = 6;
/// Fusion-weight / model-probability slots.
pub const MAX_WEIGHTS: usize = 8;
/// Version of the table layout and the meaning of its variables (part of the GUID).
/// 2: `bank_angle` also drives the filter's onboard models (MarsEntryNav) and is an input of
/// MarsEntryNavFilter.
pub const TABLE_VERSION: u32 = 2;

/// The three FMUs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Model {
    /// Entry dynamics, sensors and navigation filter (`MarsEntryNav`).
    Combined,
    /// The navigation filter alone, fed with measurements (`MarsEntryNavFilter`).
    Filter,
    /// Truth dynamics and sensors, producing the measurements (`MarsEntryTruth`).
    Truth,
}

impl Model {
    /// All models.
    pub const ALL: [Model; 3] = [Model::Combined, Model::Filter, Model::Truth];

    /// FMI model identifier (the shared library's file stem inside the `.fmu`).
    pub fn identifier(self) -> &'static str {
        match self {
            Model::Combined => "MarsEntryNav",
            Model::Filter => "MarsEntryNavFilter",
            Model::Truth => "MarsEntryTruth",
        }
    }

    /// One-line description.
    pub fn description(self) -> &'static str {
        match self {
            Model::Combined => {
                "Mars entry dynamics, sensors and navigation filter (entrynav), driven by a bank-angle command and beacon availability"
            }
            Model::Filter => {
                "Mars entry navigation filter (entrynav) alone, fed with accelerometer, air-data and radio measurements and their validity flags"
            }
            Model::Truth => {
                "Mars entry truth dynamics and sensors (entrynav): true trajectory and noisy measurements with validity flags"
            }
        }
    }

    /// Whether this model runs the truth.
    pub fn has_truth(self) -> bool {
        self != Model::Filter
    }

    /// Whether this model runs a filter.
    pub fn has_filter(self) -> bool {
        self != Model::Truth
    }

    /// The model whose GUID is `guid`.
    pub fn from_guid(guid: &str) -> Option<Model> {
        Model::ALL.into_iter().find(|m| guid_of(*m) == guid)
    }
}

/// FMI base type.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Type {
    /// fmi2Real.
    Real,
    /// fmi2Integer.
    Integer,
    /// fmi2Boolean.
    Boolean,
    /// fmi2String.
    String,
}

impl Type {
    /// Element name in the XML.
    pub fn xml(self) -> &'static str {
        match self {
            Type::Real => "Real",
            Type::Integer => "Integer",
            Type::Boolean => "Boolean",
            Type::String => "String",
        }
    }
}

/// FMI causality.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Causality {
    /// Set before initialisation, fixed afterwards.
    Parameter,
    /// Set by the master at communication points.
    Input,
    /// Computed.
    Output,
}

impl Causality {
    /// Attribute value.
    pub fn xml(self) -> &'static str {
        match self {
            Causality::Parameter => "parameter",
            Causality::Input => "input",
            Causality::Output => "output",
        }
    }
}

/// FMI variability.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Variability {
    /// Fixed after initialisation.
    Fixed,
    /// Changes only at communication points (Integer, Boolean, sampled values).
    Discrete,
    /// Real quantity of a continuous process.
    Continuous,
}

impl Variability {
    /// Attribute value.
    pub fn xml(self) -> &'static str {
        match self {
            Variability::Fixed => "fixed",
            Variability::Discrete => "discrete",
            Variability::Continuous => "continuous",
        }
    }
}

/// A variable value.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    /// Real.
    Real(f64),
    /// Integer.
    Integer(i32),
    /// Boolean.
    Boolean(bool),
    /// String.
    String(String),
}

impl Value {
    /// The value's type.
    pub fn ty(&self) -> Type {
        match self {
            Value::Real(_) => Type::Real,
            Value::Integer(_) => Type::Integer,
            Value::Boolean(_) => Type::Boolean,
            Value::String(_) => Type::String,
        }
    }

    /// As written in a `start` attribute.
    pub fn xml(&self) -> String {
        match self {
            Value::Real(v) => format!("{v:?}"),
            Value::Integer(v) => v.to_string(),
            Value::Boolean(v) => v.to_string(),
            Value::String(s) => s.clone(),
        }
    }
}

/// A measurement slot (one scalar sensor reading).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Slot {
    /// Accelerometer axis 0..3 of the IMU frame.
    Accel(u8),
    /// Dynamic pressure.
    DynamicPressure,
    /// Heating rate.
    Heating,
    /// Range to beacon slot i.
    Range(usize),
    /// Range-rate to beacon slot i.
    RangeRate(usize),
}

impl Slot {
    /// Every slot, in table order.
    pub fn all() -> Vec<Slot> {
        let mut v = vec![
            Slot::Accel(0),
            Slot::Accel(1),
            Slot::Accel(2),
            Slot::DynamicPressure,
            Slot::Heating,
        ];
        v.extend((0..MAX_BEACONS).map(Slot::Range));
        v.extend((0..MAX_BEACONS).map(Slot::RangeRate));
        v
    }

    /// The slot of a scenario channel (None for beacons past the slots).
    pub fn of(channel: Channel) -> Option<Slot> {
        let s = match channel {
            Channel::Accel(k) => Slot::Accel(k.min(2)),
            Channel::DynamicPressure => Slot::DynamicPressure,
            Channel::Heating => Slot::Heating,
            Channel::Range(i) => Slot::Range(i),
            Channel::RangeRate(i) => Slot::RangeRate(i),
        };
        match s {
            Slot::Range(i) | Slot::RangeRate(i) if i >= MAX_BEACONS => None,
            s => Some(s),
        }
    }

    fn name(self) -> String {
        match self {
            Slot::Accel(k) => format!("meas_accel_{}", ["x", "y", "z"][k as usize]),
            Slot::DynamicPressure => "meas_dynamic_pressure".into(),
            Slot::Heating => "meas_heating".into(),
            Slot::Range(i) => format!("meas_range_{}", i + 1),
            Slot::RangeRate(i) => format!("meas_range_rate_{}", i + 1),
        }
    }

    fn unit(self) -> &'static str {
        match self {
            Slot::Accel(_) => "m/s2",
            Slot::DynamicPressure => "Pa",
            Slot::Heating => "W/m2",
            Slot::Range(_) => "m",
            Slot::RangeRate(_) => "m/s",
        }
    }

    fn what(self) -> String {
        match self {
            Slot::Accel(k) => format!(
                "accelerometer specific force along IMU axis {}",
                ["x", "y", "z"][k as usize]
            ),
            Slot::DynamicPressure => "dynamic pressure (air data)".into(),
            Slot::Heating => "convective heating rate (air data)".into(),
            Slot::Range(i) => format!("two-way range to beacon {}", i + 1),
            Slot::RangeRate(i) => format!("range-rate to beacon {}", i + 1),
        }
    }
}

/// What a variable is bound to.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Key {
    /// Scenario: built-in name or file in the FMU's resources.
    Scenario,
    /// Filter name.
    Filter,
    /// Generator seed.
    Seed,
    /// Draw the truth from the scenario's dispersions.
    Dispersed,
    /// Bank-angle command \[rad\].
    Bank,
    /// Beacon slot commanded available.
    BeaconAvailable(usize),
    /// A measurement epoch is present (filter input / truth output).
    MeasEpoch,
    /// Time the measurements were taken.
    MeasTime,
    /// Measurement value.
    Meas(Slot),
    /// Measurement validity flag.
    MeasValid(Slot),
    /// Planet-relative spherical truth component k = r, lon, lat, v, fpa, heading.
    TruthSph(usize),
    /// Truth altitude.
    TruthAltitude,
    /// True density.
    TruthDensity,
    /// True dynamic pressure.
    TruthDynamicPressure,
    /// True heating rate.
    TruthHeating,
    /// Magnitude of the aerodynamic acceleration.
    TruthAeroAccel,
    /// Noiseless accelerometer reading, IMU axis k.
    TruthSensedAccel(usize),
    /// Geometric range to beacon slot i.
    BeaconRange(usize),
    /// Beacon slot i above the horizon.
    BeaconVisible(usize),
    /// Why the truth stopped.
    TruthStop,
    /// Number of beacons.
    NBeacons,
    /// Epoch of the estimate.
    NavTime,
    /// Filter status.
    NavStatus,
    /// Filter state dimension.
    NStates,
    /// Estimate, state slot i.
    EstX(usize),
    /// 1σ, state slot i.
    EstSigma(usize),
    /// Estimate as planet-relative spherical component k.
    EstSph(usize),
    /// Estimated density.
    EstDensity,
    /// Normalised innovation squared of the last update.
    Nis,
    /// Scalar measurements used in the last update.
    NMeas,
    /// Fusion weight / model probability i.
    Weight(usize),
    /// Number of weights.
    NWeights,
    /// Truth in filter coordinates at the estimate's epoch, slot i.
    TruthX(usize),
    /// Estimation error, slot i.
    Err(usize),
    /// NEES.
    Nees,
    /// NEES degrees of freedom.
    NeesDof,
    /// True density at the estimate's epoch.
    NavTruthDensity,
}

/// One scalar variable.
#[derive(Debug, Clone, PartialEq)]
pub struct Var {
    /// Value reference (unique across all types within one model).
    pub vr: u32,
    /// Name.
    pub name: String,
    /// Base type.
    pub ty: Type,
    /// Causality.
    pub causality: Causality,
    /// Variability.
    pub variability: Variability,
    /// Unit (declared in `UnitDefinitions`).
    pub unit: Option<&'static str>,
    /// Start value (parameters and inputs).
    pub start: Option<Value>,
    /// Description.
    pub description: String,
    /// What it is bound to.
    pub key: Key,
}

impl Var {
    /// Whether the master may set it (parameters and inputs).
    pub fn settable(&self) -> bool {
        self.causality != Causality::Output
    }
}

/// A unit: name, SI base-unit exponents (kg, m, s, rad), and an optional display unit (name, factor).
pub type UnitDef = (&'static str, [i32; 4], Option<(&'static str, f64)>);

/// The units the variables use.
pub const UNITS: [UnitDef; 8] = [
    ("m", [0, 1, 0, 0], None),
    ("rad", [0, 0, 0, 1], Some(("deg", 57.29577951308232))),
    ("m/s", [0, 1, -1, 0], None),
    ("m/s2", [0, 1, -2, 0], None),
    ("s", [0, 0, 1, 0], None),
    ("kg/m3", [1, -3, 0, 0], None),
    ("Pa", [1, -1, -2, 0], None),
    ("W/m2", [1, 0, -3, 0], None),
];

/// Default parameter values.
pub const DEFAULT_SCENARIO: &str = "four-beacon-fusion";
/// Default filter.
pub const DEFAULT_FILTER: &str = "dcifaif";
/// Default seed.
pub const DEFAULT_SEED: i32 = 1;

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

/// FNV-1a, 64 bit.
pub fn fnv1a64(bytes: &[u8], seed: u64) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64 ^ seed;
    for b in bytes {
        h ^= *b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// The GUID of `model`: a hash of its identifier, the table version and every variable's
/// value reference, name, type, causality, variability, unit and start value.
pub fn guid_of(model: Model) -> String {
    let mut text = format!("{}|{}\n", model.identifier(), TABLE_VERSION);
    for v in variables(model) {
        text.push_str(&format!(
            "{}|{}|{}|{}|{}|{}|{}\n",
            v.vr,
            v.name,
            v.ty.xml(),
            v.causality.xml(),
            v.variability.xml(),
            v.unit.unwrap_or(""),
            v.start.as_ref().map(Value::xml).unwrap_or_default()
        ));
    }
    let a = fnv1a64(text.as_bytes(), 0);
    let b = fnv1a64(text.as_bytes(), 0x5bd1_e995);
    format!(
        "{{{:08x}-{:04x}-{:04x}-{:04x}-{:012x}}}",
        (a >> 32) as u32,
        (a >> 16) as u16,
        a as u16,
        (b >> 48) as u16,
        b & 0xffff_ffff_ffff
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::HashSet;

    #[test]
    fn names_and_refs_unique_guids_distinct() {
        let mut guids = HashSet::new();
        for m in Model::ALL {
            let vars = variables(m);
            let names: HashSet<_> = vars.iter().map(|v| v.name.clone()).collect();
            assert_eq!(names.len(), vars.len());
            for (i, v) in vars.iter().enumerate() {
                assert_eq!(v.vr as usize, i);
                assert_eq!(v.settable(), v.start.is_some(), "{}", v.name);
            }
            assert!(guids.insert(guid_of(m)));
            assert_eq!(Model::from_guid(&guid_of(m)), Some(m));
        }
        assert_eq!(Model::from_guid("{nope}"), None);
    }
}
