//! `trade --grid FILE --method lincov`: a grid cell's row from LinCov of one filter
//! (`entrynav::sim::lincov`) instead of a Monte Carlo — the same columns where they mean
//! the same (predicted position and velocity RMSE, predicted ANEES), none where they do not
//! (±3σ fractions, diverged runs, CPU per step).

use crate::grid::CellRow;
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::Scenario;
use entrynav::sim::lincov::entry_lincov;

/// The row of filter `kind` in a cell; a filter or scenario LinCov cannot analyse is a refused
/// row naming why.
pub fn row(
    scenario: &Scenario,
    kind: FilterKind,
    cell: &str,
    variation: &str,
    min_delta_scaled: Option<f64>,
) -> CellRow {
    let mut row = CellRow {
        cell: cell.to_string(),
        scenario: scenario.config.name.clone(),
        variation: variation.to_string(),
        filter: kind.name().to_string(),
        refused: None,
        pos_rmse_final_m: None,
        vel_rmse_final_mps: None,
        pos_rmse_avg_m: None,
        anees: None,
        min_within_3sigma: None,
        diverged: None,
        us_per_step: None,
        min_delta_scaled,
        delivery: None,
    };
    match entry_lincov(scenario, kind) {
        Ok(l) => {
            let finite = |v: f64| v.is_finite().then_some(v);
            row.pos_rmse_final_m = finite(l.final_value(|e| e.pos_m));
            row.vel_rmse_final_mps = finite(l.final_value(|e| e.vel_mps));
            row.pos_rmse_avg_m = finite(l.time_avg(|e| e.pos_m));
            row.anees = finite(l.time_avg(|e| e.nees));
        }
        Err(e) => row.refused = Some(format!("LinCov: {e}")),
    }
    row
}
