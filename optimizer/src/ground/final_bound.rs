//! The final position PCRLB of a scenario on one truth run: the objective of `optimize orbiters
//! --objective pcrlb`.

use crate::error::OptimizerError;
use entrynav::scenario::Scenario;
use entrynav::scenario::ScenarioConfig;

/// Master seed of the truth run behind `optimize orbiters --objective pcrlb`.
pub const PCRLB_SEED: u64 = 1;

/// Truth runs that bound averages over (one: common random numbers for every candidate, so the
/// objective is a smooth function of the elements).
pub const PCRLB_RUNS: usize = 1;

/// Final position PCRLB \[m\] of scenario `cfg` on run 0 of seed [`PCRLB_SEED`] (the bound a
/// `trade --seed 1` reports for its first run): the objective of `optimize orbiters --objective
/// pcrlb`.
pub(crate) fn final_position_bound_of(cfg: ScenarioConfig) -> Result<f64, OptimizerError> {
    let name = cfg.name.clone();
    let scenario = Scenario::build(cfg, &entrynav::files::no_files)?;
    let bound = entrynav::sim::pcrlb_study(&scenario, PCRLB_SEED, PCRLB_RUNS)?;
    match bound.final_.get("pos_m").copied().flatten() {
        Some(v) if bound.available && v.is_finite() => Ok(v),
        _ => Err(OptimizerError::InvalidInput(format!(
            "no PCRLB for scenario '{name}': {}",
            bound.reason.as_deref().unwrap_or("non-finite bound")
        ))),
    }
}
