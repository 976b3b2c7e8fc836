//! The scenario a study runs on ([`input`]) and the truth atmosphere a density table replaces
//! ([`truth_atmosphere`]).

pub mod input;
pub mod truth_atmosphere;

pub use input::ScenarioInput;
pub use truth_atmosphere::TruthAtmosphere;
