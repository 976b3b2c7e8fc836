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

mod defaults;
mod enums;
pub mod fmi3;
mod guid;
mod model;
mod sizes;
mod slot;
mod spec;
mod specific;
mod table;
mod units;
mod var;

pub use defaults::{
    DEFAULT_FILTER, DEFAULT_SCENARIO, DEFAULT_SEED, GUIDED_FILTER, GUIDED_SCENARIO_FILE,
};
pub use enums::{ENUM_TYPES, EnumType, GUIDANCE_STATUS, NAV_STATUS, TRUTH_STOP};
pub use guid::{TABLE_DATE, TABLE_VERSION, fnv1a64};
pub use model::Model;
pub use sizes::{MAX_BEACONS, MAX_STATES, MAX_WEIGHTS};
pub use slot::{Key, Slot};
pub use spec::{ModelSpec, SpecError, guid_of};
pub use specific::{Specific, StateVar, specific_identifier};
pub use table::guidance::{entry_estimate, guided_scenario, guided_scenario_toml};
pub use table::variables;
pub use units::{UNITS, UnitDef};
pub use var::{Causality, Type, Value, Var, Variability};
