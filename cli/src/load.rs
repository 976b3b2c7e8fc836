//! Resolve `--scenario NAME|FILE` and the files a scenario refers to.

use anyhow::{Context, Result, bail};
use entrynav::scenario::{BUILTIN_NAMES, Scenario, ScenarioConfig};
use std::path::{Path, PathBuf};

/// The configuration for a built-in name or a TOML file, and the directory relative paths in it
/// resolve against (the file's directory; the current directory for built-ins).
pub fn scenario_config(name_or_file: &str) -> Result<(ScenarioConfig, PathBuf)> {
    if BUILTIN_NAMES.contains(&name_or_file) {
        return Ok((ScenarioConfig::builtin(name_or_file)?, PathBuf::from(".")));
    }
    let path = Path::new(name_or_file);
    if !path.exists() {
        bail!(
            "scenario '{name_or_file}' is neither a built-in ({}) nor an existing file",
            BUILTIN_NAMES.join(", ")
        );
    }
    let text = std::fs::read_to_string(path)
        .with_context(|| format!("cannot read scenario file {}", path.display()))?;
    let cfg = ScenarioConfig::from_toml_str(&text, &path.display().to_string())?;
    let dir = path
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from("."));
    Ok((cfg, dir))
}

/// Build a runnable scenario, reading referenced files relative to `dir`.
pub fn build(cfg: ScenarioConfig, dir: &Path) -> Result<Scenario> {
    let dir = dir.to_path_buf();
    let load = move |p: &str| -> std::result::Result<String, String> {
        let path = if Path::new(p).is_absolute() {
            PathBuf::from(p)
        } else {
            dir.join(p)
        };
        std::fs::read_to_string(&path).map_err(|e| format!("cannot read {}: {e}", path.display()))
    };
    Ok(Scenario::build(cfg, &load)?)
}
