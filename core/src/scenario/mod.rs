//! Scenarios: the TOML description of an entry (truth, filter model, sensors, beacons,
//! dispersions, timing), its validation, the built-in set, and the runtime [`Scenario`].
//!
//! Every error names the field, the value and the allowed range. The core does no I/O: callers
//! pass the file text, and a `load` callback for files a scenario refers to (tabulated
//! atmospheres), so the CLI and the FMU can resolve paths their own way.

pub mod build;
pub mod builtin;
pub mod config;
pub mod draw;
pub mod error;
pub mod noise_inflation;
mod onboard;
pub mod plausibility;
pub mod reference;
mod toml_text;
mod truth_values;
pub mod validate;
mod validate_density;
mod validate_faults;
mod validate_filter;
mod validate_guidance;
mod validate_range;
mod validate_state;
mod with_beacons;

pub use build::Scenario;
pub use builtin::{BUILTIN_NAMES, builtin_toml};
pub use config::*;
pub use draw::TruthDraw;
pub use error::ScenarioError;
