//! What every `entrynav optimize` problem reads and writes: the scenario (with a warning for each
//! implausible value), its result files (whole or absent) and their `wrote FILE` lines.

use crate::args::ScenarioArgs;
use anyhow::{Context, Result};
use entrynav_studies::ScenarioInput;
use serde_json::Value;
use std::path::Path;

/// The scenario with its overrides, warning on standard error about implausible values.
pub fn load_input(s: &ScenarioArgs) -> Result<ScenarioInput> {
    let input = ScenarioInput::resolve(&s.scenario, &s.overrides.sets)?;
    crate::preflight::warn_implausible(&input.config);
    Ok(input)
}

/// Write `text` to `path` (its folder created).
pub fn write_text(path: &Path, text: &str) -> Result<()> {
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("cannot create {}", parent.display()))?;
    }
    Ok(entrynav_studies::output::atomic_file::write(path, text)?)
}

/// `v` as the text of a JSON file.
pub fn json_text(v: &Value) -> Result<String> {
    Ok(serde_json::to_string_pretty(v)? + "\n")
}

/// Write `path` with `write` when it is asked for, and say so.
pub fn tell(path: Option<&Path>, write: impl FnOnce(&Path) -> Result<()>) -> Result<()> {
    if let Some(path) = path {
        write(path)?;
        println!("wrote {}", path.display());
    }
    Ok(())
}
