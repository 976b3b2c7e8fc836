//! The variable list of each FMU, declared once (the get/set code and the model description are
//! both generated from it), one function per group of variables: the parameters
//! ([`params`](mod@params)), the inputs ([`inputs`]), the outputs of the truth ([`truth`]), of the
//! filter ([`nav`]), of their judgement ([`judgement`]), of the guidance FMU ([`guidance`]) and of
//! the guided FMU ([`guided`]).

mod builder;
pub(super) mod guidance;
mod guided;
mod inputs;
mod judgement;
mod nav;
mod params;
mod truth;

use super::model::Model;
use super::sizes::MAX_BEACONS;
use super::specific::Specific;
use super::var::Var;
use builder::Builder;

/// The variables of the generic `model`, in value-reference order.
pub fn variables(model: Model) -> Vec<Var> {
    build(model, None)
}

/// The variables of `model`, generic or specific to an embedded scenario.
pub(super) fn build(model: Model, specific: Option<&Specific>) -> Vec<Var> {
    let mut b = Builder { vars: Vec::new() };
    if model == Model::Guidance {
        guidance::guided_scenario_param(&mut b);
        guidance::guidance_vars(&mut b);
        return b.vars;
    }
    if model == Model::Guided {
        guidance::guided_scenario_param(&mut b);
    } else if specific.is_none() {
        params::scenario_param(&mut b);
    }
    params::filter_param(&mut b, model, specific);
    params::draw_params(&mut b, model);
    if specific.is_none() {
        params::allow_external_files(&mut b);
    }
    let n_beacons = specific
        .map(|s| s.scenario.beacons.len().min(MAX_BEACONS))
        .unwrap_or(MAX_BEACONS);
    inputs::bank_input(&mut b, model);
    inputs::beacon_inputs(&mut b, model, n_beacons);
    inputs::measurements(&mut b, model);
    if model.has_truth() {
        truth::truth_outputs(&mut b, n_beacons);
    }
    if model.has_filter() {
        nav::nav_outputs(&mut b, specific);
    }
    if model.is_closed() {
        judgement::judgement_outputs(&mut b, specific);
    }
    if model == Model::Guided {
        guided::guided_outputs(&mut b);
    }
    b.vars
}
