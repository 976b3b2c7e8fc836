//! Resolve `--scenario NAME|FILE` and the files a scenario refers to.

use anyhow::{Context, Result, bail};
use entrynav::scenario::{BUILTIN_NAMES, Scenario, ScenarioConfig};
use std::path::{Path, PathBuf};

/// Apply `--set path=value` overrides (TOML dotted path, TOML value syntax) to a scenario and
/// re-validate it, e.g. `truth.density_bias=0.095` or `dispersions.density_bias=0`.
pub fn apply_overrides(cfg: ScenarioConfig, sets: &[String]) -> Result<ScenarioConfig> {
    if sets.is_empty() {
        return Ok(cfg);
    }
    let mut doc: toml::Table = toml::from_str(&cfg.to_toml_string())?;
    for set in sets {
        let (path, value) = set.split_once('=').with_context(|| {
            format!("--set '{set}': expected PATH=VALUE, e.g. truth.density_bias=0.095")
        })?;
        let value: toml::Value = match toml::from_str::<toml::Table>(&format!("v = {value}")) {
            Ok(mut t) => t
                .remove("v")
                .unwrap_or(toml::Value::String(value.to_string())),
            Err(_) => toml::Value::String(value.to_string()),
        };
        let keys: Vec<&str> = path.trim().split('.').collect();
        let mut table = &mut doc;
        for k in &keys[..keys.len() - 1] {
            table = table
                .entry(k.to_string())
                .or_insert_with(|| toml::Value::Table(toml::Table::new()))
                .as_table_mut()
                .with_context(|| format!("--set '{set}': '{k}' is not a table"))?;
        }
        table.insert(keys[keys.len() - 1].to_string(), value);
    }
    let text = toml::to_string(&doc)?;
    Ok(ScenarioConfig::from_toml_str(
        &text,
        "scenario with --set overrides",
    )?)
}

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
