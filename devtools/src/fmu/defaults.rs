//! The parameters an instance of a model starts with when they are not the generic defaults.

use entrynav_fmu::vars::{GUIDED_FILTER, GUIDED_SCENARIO_FILE, Model, ModelSpec};

/// The scenario and filter an instance of `spec` starts with, when they are not the generic
/// defaults: the embedded scenario and default filter of a specific FMU, the guided scenario and
/// filter of `MarsEntryNavGuided`.
pub(super) fn start_params(spec: &ModelSpec) -> Option<(&str, &'static str)> {
    match spec.specific() {
        Some(sp) => Some((sp.scenario.config.name.as_str(), sp.filter.name())),
        None if spec.model() == Model::Guided => Some((GUIDED_SCENARIO_FILE, GUIDED_FILTER)),
        None => None,
    }
}
