//! A [`ScenarioConfig`] from and to TOML text: parsed, validated, serialised back; and the
//! built-in scenarios by name.

use super::builtin::{BUILTIN_NAMES, builtin_toml};
use super::config::ScenarioConfig;
use super::error::ScenarioError;

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
