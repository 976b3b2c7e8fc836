//! The variable table: one list per FMU, used by the get/set code and by the `modelDescription.xml`
//! generator, so the two cannot disagree. The GUID is a hash of the table.
//!
//! The generic layout is fixed whatever the scenario: filter states in slots 1..=12 (slots past the
//! scenario's state dimension read 0), beacons in slots 1..=6 (past the scenario's beacon count:
//! 0 / false), fusion weights or model probabilities in slots 1..=8. No output is ever NaN (system
//! masters such as OMSimulator reject a NaN and drop the whole result row): values that are not
//! defined read 0 beside the output that says so (the NIS while `n_meas` = 0, the NEES while
//! `nees_dof` = 0, the truth of a state without truth counterpart such as ρ0 under a
//! non-exponential truth atmosphere, the density estimate of a filter without one). A
//! scenario-specific FMU ([`ModelSpec::for_scenario`]) names its state outputs after the scenario's
//! states instead (`est.r` in m, `est.lon` in rad, …) and has one beacon slot per beacon.

pub mod fmi3;
mod model;
mod slot;
mod table;
mod table_guidance;
mod table_outputs;

pub use model::{
    Model, ModelSpec, SpecError, Specific, StateVar, guided_scenario, specific_identifier,
};
pub use slot::{Key, Slot};
pub use table::variables;
pub use table_guidance::{GUIDED_FILTER, GUIDED_SCENARIO_FILE, guided_scenario_toml};

/// Filter state slots of the generic FMUs: every supported filter dimension.
pub const MAX_STATES: usize = entrynav::state_dim::MAX_STATE_DIM;
/// Beacon slots.
pub const MAX_BEACONS: usize = 6;
/// Fusion-weight / model-probability slots.
pub const MAX_WEIGHTS: usize = 8;
/// Version of the table layout and the meaning of its variables (part of the GUID).
/// 2: `bank_angle` also drives the filter's onboard models (MarsEntryNav) and is an input of
/// MarsEntryNavFilter.
/// 3: `allow_external_files`; Enumeration types for `nav_status` and `truth_stop` (with Integer
/// twins `nav_status_code`, `truth_stop_code`); estimate outputs `discrete`; dimensionless units;
/// no input feeds through (`dependencies`).
/// 4: no output is NaN: undefined values (NIS before the first update, NEES without truth, the
/// density estimate of a filter without one, the truth of a state without truth counterpart)
/// read 0.
pub const TABLE_VERSION: u32 = 4;
/// `generationDateAndTime` of every description of [`TABLE_VERSION`]: the description is a pure
/// function of the table, so it carries the table's date and is reproducible byte for byte.
pub const TABLE_DATE: &str = "2026-12-04T00:00:00Z";

/// FMI base type (how a value crosses the C API: Enumerations go through fmi2Get/SetInteger).
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
    /// Changes only at communication points: Integer, Boolean, and Reals of a sampled-data system
    /// (the measurements and the estimate, which change only at measurement epochs).
    Discrete,
    /// Real quantity of a continuous process (the truth).
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
    /// Integer (and Enumeration).
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

/// An FMI Enumeration type (`TypeDefinitions/SimpleType`): item `k` has the value `k`.
#[derive(Debug, PartialEq, Eq, Hash)]
pub struct EnumType {
    /// Type name (`declaredType`).
    pub name: &'static str,
    /// Description.
    pub description: &'static str,
    /// Items (name, description), valued 0, 1, ….
    pub items: &'static [(&'static str, &'static str)],
}

/// `nav_status`: [`entrynav::sim::engine::NavStatus::code`].
pub static NAV_STATUS: EnumType = EnumType {
    name: "NavStatus",
    description: "Navigation filter health",
    items: &[
        (
            "initial",
            "No measurement epoch processed yet: the estimate is the filter start",
        ),
        ("running", "Processing measurement epochs"),
        (
            "failed",
            "Stopped on a numerical failure (reason logged); the estimate is frozen",
        ),
    ],
};

/// `truth_stop`: why the truth stopped.
pub static TRUTH_STOP: EnumType = EnumType {
    name: "TruthStop",
    description: "Why the truth trajectory stopped",
    items: &[
        ("running", "The truth is still being integrated"),
        ("duration", "The scenario duration was reached"),
        ("stop_speed", "The airspeed fell below the stop speed"),
        ("ground", "The altitude reached zero"),
    ],
};

/// Every Enumeration type a table may use.
pub static ENUM_TYPES: [&EnumType; 2] = [&NAV_STATUS, &TRUTH_STOP];

/// One scalar variable.
#[derive(Debug, Clone, PartialEq)]
pub struct Var {
    /// Value reference (unique across all types within one model).
    pub vr: u32,
    /// Name.
    pub name: String,
    /// Base type (an Enumeration is accessed as Integer).
    pub ty: Type,
    /// The Enumeration type, for Integer variables declared as one.
    pub declared: Option<&'static EnumType>,
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

    /// Element name of its type in the XML (`Enumeration` for a declared Enumeration).
    pub fn xml_type(&self) -> &'static str {
        if self.declared.is_some() {
            "Enumeration"
        } else {
            self.ty.xml()
        }
    }
}

/// A unit: name, SI base-unit exponents (kg, m, s, rad), and an optional display unit (name, factor).
pub type UnitDef = (&'static str, [i32; 4], Option<(&'static str, f64)>);

/// The units the variables use ("1": dimensionless).
pub const UNITS: [UnitDef; 11] = [
    ("m", [0, 1, 0, 0], None),
    ("rad", [0, 0, 0, 1], Some(("deg", 57.29577951308232))),
    ("m/s", [0, 1, -1, 0], None),
    ("m/s2", [0, 1, -2, 0], None),
    ("s", [0, 0, 1, 0], None),
    ("kg/m3", [1, -3, 0, 0], None),
    ("Pa", [1, -1, -2, 0], None),
    ("W/m2", [1, 0, -3, 0], None),
    ("m2/kg", [-1, 2, 0, 0], None),
    ("1", [0, 0, 0, 0], None),
    ("rad/s", [0, 0, -1, 1], Some(("deg/s", 57.29577951308232))),
];

/// Default parameter values.
pub const DEFAULT_SCENARIO: &str = "four-beacon-fusion";
/// Default filter.
pub const DEFAULT_FILTER: &str = "dcifaif";
/// Default seed.
pub const DEFAULT_SEED: i32 = 1;

/// FNV-1a, 64 bit.
pub fn fnv1a64(bytes: &[u8], seed: u64) -> u64 {
    let mut h = 0xcbf2_9ce4_8422_2325u64 ^ seed;
    for b in bytes {
        h ^= *b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// A GUID from a hash of `identifier`, the table version, `extra` (the embedded scenario of a
/// specific FMU) and every variable's reference, name, type, Enumeration type, causality,
/// variability, unit and start value.
pub(crate) fn table_guid(identifier: &str, extra: &str, vars: &[Var]) -> String {
    let mut text = format!("{identifier}|{TABLE_VERSION}|{extra}\n");
    for v in vars {
        let declared = v
            .declared
            .map(|e| {
                let items: Vec<&str> = e.items.iter().map(|i| i.0).collect();
                format!("{}={}", e.name, items.join(","))
            })
            .unwrap_or_default();
        text.push_str(&format!(
            "{}|{}|{}|{}|{}|{}|{}|{}\n",
            v.vr,
            v.name,
            v.ty.xml(),
            declared,
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

/// The GUID of the generic `model`.
pub fn guid_of(model: Model) -> String {
    table_guid(model.identifier(), "", &variables(model))
}

#[cfg(test)]
mod tests {
    use super::*;
    use entrynav::scenario::ScenarioConfig;
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
                assert!(v.declared.is_none() || v.ty == Type::Integer, "{}", v.name);
                if let Some(u) = v.unit {
                    assert!(UNITS.iter().any(|d| d.0 == u), "{}: unit {u}", v.name);
                }
            }
            assert!(guids.insert(guid_of(m)));
            assert_eq!(Model::from_guid(&guid_of(m)), Some(m));
            assert_eq!(ModelSpec::generic(m).guid(), guid_of(m));
        }
        assert_eq!(Model::from_guid("{nope}"), None);
    }

    #[test]
    fn the_guided_scenario_builds_with_guidance_and_an_accelerometer_triad() {
        let s = guided_scenario().unwrap();
        assert_eq!(s.config.name, "msl-guided");
        assert!(s.build_guidance().unwrap().is_ok());
        let (_, stop, step) = ModelSpec::generic(Model::Guidance).default_experiment();
        let period = s.config.guidance.as_ref().unwrap().period_s();
        assert_eq!((stop, step), (s.config.timing.duration_s, period));
        // Without the section (and with msl-airdata's name, description and constant bank) it
        // is msl-airdata again.
        let base = ScenarioConfig::builtin("msl-airdata").unwrap();
        let mut cfg = s.config.clone();
        cfg.guidance = None;
        cfg.name = base.name.clone();
        cfg.description = base.description.clone();
        cfg.truth.bank_deg = base.truth.bank_deg;
        assert_eq!(cfg.to_toml_string(), base.to_toml_string());
    }
}
