//! Scenarios across the boundary: as their TOML text and the folder their relative file names
//! resolve against, so a Python `Scenario` is a value that `to_toml()` prints exactly; every
//! change goes through the loader's `--set` path and validation.

use crate::errors::{json_err, load_err, study_err};
use entrynav::scenario::{BUILTIN_NAMES, Scenario, ScenarioConfig};
use entrynav_loader as load;
use entrynav_studies::ScenarioInput;
use pyo3::prelude::*;
use std::path::Path;

fn config_of(toml: &str) -> PyResult<ScenarioConfig> {
    ScenarioConfig::from_toml_str(toml, "scenario").map_err(|e| study_err(e.into()))
}

/// The scenario `toml` (relative file names against `dir`) as a study's input.
pub fn input(toml: &str, dir: &str) -> PyResult<ScenarioInput> {
    ScenarioInput::from_toml(toml, Path::new(dir), &[]).map_err(study_err)
}

/// `[(name, one-line summary)]` of every built-in scenario.
#[pyfunction]
pub fn builtin_scenarios() -> PyResult<Vec<(String, String)>> {
    BUILTIN_NAMES
        .iter()
        .map(|name| {
            let cfg = ScenarioConfig::builtin(name).map_err(|e| study_err(e.into()))?;
            let sc = Scenario::build(cfg, &entrynav::files::no_files)
                .map_err(|e| study_err(e.into()))?;
            Ok((name.to_string(), load::summary::summary(&sc)))
        })
        .collect()
}

/// A built-in name or a TOML file (relative to the working directory): `(toml, folder)`.
#[pyfunction]
pub fn resolve_scenario(name_or_file: &str) -> PyResult<(String, String)> {
    let (cfg, dir) = load::resolve(name_or_file, load::Base::CurrentDir)
        .map_err(load_err)?
        .into_parts();
    Ok((cfg.to_toml_string(), dir.display().to_string()))
}

/// The scenario `toml` with `PATH=VALUE` overrides applied and validated: its new TOML text.
#[pyfunction]
pub fn apply_sets(toml: &str, sets: Vec<String>) -> PyResult<String> {
    let cfg = load::apply_overrides(config_of(toml)?, &sets).map_err(load_err)?;
    Ok(cfg.to_toml_string())
}

/// The scenario as JSON (every field, defaults filled in).
#[pyfunction]
pub fn scenario_json(toml: &str) -> PyResult<String> {
    serde_json::to_string(&config_of(toml)?).map_err(json_err)
}
