//! What a check run flies: its scenario (the embedded one of a specific FMU, else the
//! `--scenario` or the model's default) and its filter.

use super::args::CheckArgs;
use super::inputs::load_scenario;
use crate::fmu::defaults::start_params;
use anyhow::Result;
use entrynav::scenario::Scenario;
use entrynav_fmi_host::Unpacked;
use entrynav_fmu::ModelSpec;
use entrynav_fmu::vars::{DEFAULT_FILTER, DEFAULT_SCENARIO, GUIDED_SCENARIO_FILE, Model};
use std::path::Path;
use std::sync::Arc;

/// The scenario a check runs: `--scenario`, else the guided scenario for the guidance and guided
/// FMUs and four-beacon-fusion for the others.
pub(super) fn scenario_param(a: &CheckArgs, m: Model) -> String {
    a.scenario.clone().unwrap_or_else(|| {
        match m {
            Model::Guidance | Model::Guided => GUIDED_SCENARIO_FILE,
            _ => DEFAULT_SCENARIO,
        }
        .to_string()
    })
}

/// The filter a check runs: `--filter`, else the FMU's default.
pub(super) fn filter_of(a: &CheckArgs, spec: &ModelSpec) -> String {
    a.filter.clone().unwrap_or_else(|| {
        start_params(spec)
            .map(|(_, f)| f)
            .unwrap_or(DEFAULT_FILTER)
            .to_string()
    })
}

/// The scenario a check runs: the embedded one of a specific FMU, else `name` from `resources`.
pub(super) fn check_scenario(u: &Unpacked, name: &str, resources: &Path) -> Result<Arc<Scenario>> {
    match u.spec.specific() {
        Some(s) => Ok(Arc::clone(&s.scenario)),
        None => load_scenario(name, resources),
    }
}
