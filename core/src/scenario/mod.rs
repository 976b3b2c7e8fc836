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
mod onboard;
pub mod plausibility;
pub mod reference;
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

impl ScenarioConfig {
    /// Parse and validate a scenario from TOML text; `source_name` (a file name or `builtin:NAME`)
    /// appears in errors.
    pub fn from_toml_str(text: &str, source_name: &str) -> Result<ScenarioConfig, ScenarioError> {
        let cfg: ScenarioConfig = toml::from_str(text).map_err(|e| ScenarioError::Parse {
            source_name: source_name.to_string(),
            message: e.to_string().trim_end().to_string(),
        })?;
        cfg.validate()?;
        Ok(cfg)
    }

    /// The built-in scenario `name`, parsed and validated.
    pub fn builtin(name: &str) -> Result<ScenarioConfig, ScenarioError> {
        let text = builtin_toml(name).ok_or_else(|| ScenarioError::UnknownBuiltin {
            name: name.to_string(),
            known: BUILTIN_NAMES.join(", "),
        })?;
        ScenarioConfig::from_toml_str(text, &format!("builtin:{name}"))
    }

    /// Serialise back to TOML.
    pub fn to_toml_string(&self) -> String {
        toml::to_string_pretty(self).unwrap_or_else(|e| format!("# serialisation failed: {e}\n"))
    }
}
