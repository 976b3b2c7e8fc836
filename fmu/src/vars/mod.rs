//! The variable table: one list per FMU, used by the get/set code and by the `modelDescription.xml`
//! generator, so the two cannot disagree. The GUID is a hash of the table.
//!
//! The layout is fixed whatever the scenario: filter states in slots 1..=12 (slots past the
//! scenario's state dimension read 0), beacons in slots 1..=6 (past the scenario's beacon count:
//! 0 / false), fusion weights or model probabilities in slots 1..=8. Values that exist but are not
//! known read NaN (the truth of ρ0 when the truth atmosphere is not exponential, the NEES before it
//! is defined, the density estimate of a filter that does not estimate density).

use entrynav::sensors::Channel;

/// Filter state slots.
pub const MAX_STATES: usize = entrynav::state_dim::MAX_STATE_DIM;
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

mod table;

pub use table::variables;

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
