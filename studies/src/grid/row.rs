//! A grid's rows: one per cell and filter, from the cell's Monte Carlo (with, for a scenario
//! with `[guidance]`, the filter's delivery at deployment on the same runs), from LinCov of the
//! filter (`--method lincov`: the same columns where they mean the same — predicted position and
//! velocity RMSE, predicted ANEES — none where they do not), or refused (the filter does not fit
//! the cell).

use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::Scenario;
use entrynav::sim::FilterReport;
use entrynav::sim::guided::delivery::{DeliveryRow, run_delivery};
use entrynav::sim::lincov::entry_lincov;
use serde::Serialize;

/// One filter's delivery in one cell.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct CellDelivery {
    /// RMS miss distance over the runs that deployed \[m\].
    pub rms_miss_m: Option<f64>,
    /// Semi-major axis of the 99 % delivery ellipse \[m\].
    pub ellipse_99_semi_major_m: Option<f64>,
    /// Semi-minor axis of the 99 % delivery ellipse \[m\].
    pub ellipse_99_semi_minor_m: Option<f64>,
    /// Runs that did not deploy (counted, not dropped).
    pub failures: usize,
    /// Perfect navigation's RMS miss on the same runs \[m\].
    pub perfect_nav_rms_miss_m: Option<f64>,
    /// Perfect navigation's failures on the same runs.
    pub perfect_nav_failures: usize,
}

/// One cell's result for one filter.
#[derive(Debug, Clone, Serialize)]
pub struct CellRow {
    /// Cell label.
    pub cell: String,
    /// Scenario name.
    pub scenario: String,
    /// Variation values.
    pub variation: String,
    /// Filter name.
    pub filter: String,
    /// Refused (does not fit) — reason.
    pub refused: Option<String>,
    /// Position RMSE at the final epoch (m).
    pub pos_rmse_final_m: Option<f64>,
    /// Velocity RMSE at the final epoch [m/s].
    pub vel_rmse_final_mps: Option<f64>,
    /// Time-averaged position RMSE (m).
    pub pos_rmse_avg_m: Option<f64>,
    /// ANEES.
    pub anees: Option<f64>,
    /// Smallest per-state fraction of samples inside ±3σ.
    pub min_within_3sigma: Option<f64>,
    /// Diverged runs.
    pub diverged: Option<u64>,
    /// CPU per step (µs) (Markdown and CSV; in the JSON it is under `timing`, the one block
    /// that is not reproducible).
    #[serde(skip)]
    pub us_per_step: Option<f64>,
    /// Minimum scaled observability degree of the centralised system along the nominal entry.
    pub min_delta_scaled: Option<f64>,
    /// A Monte Carlo cell with `[guidance]`: the filter's delivery at deployment.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub delivery: Option<CellDelivery>,
}

impl CellRow {
    /// A row of `filter` in cell `cell` (variation `variation`) of `scenario`, every figure
    /// absent.
    pub fn empty(cell: &str, scenario: &Scenario, variation: &str, filter: &str) -> CellRow {
        CellRow {
            cell: cell.to_string(),
            scenario: scenario.config.name.clone(),
            variation: variation.to_string(),
            filter: filter.to_string(),
            refused: None,
            pos_rmse_final_m: None,
            vel_rmse_final_mps: None,
            pos_rmse_avg_m: None,
            anees: None,
            min_within_3sigma: None,
            diverged: None,
            us_per_step: None,
            min_delta_scaled: None,
            delivery: None,
        }
    }

    /// The row of filter `kind` by LinCov; a filter or scenario LinCov cannot analyse is a
    /// refused row naming why.
    pub fn lincov(self, scenario: &Scenario, kind: FilterKind) -> CellRow {
        let mut row = self;
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

    /// The row of filter report `f` of the cell's Monte Carlo.
    pub fn monte_carlo(self, f: &FilterReport, delivery: Option<CellDelivery>) -> CellRow {
        CellRow {
            pos_rmse_final_m: f.rmse_final.get("pos_m").copied().flatten(),
            vel_rmse_final_mps: f.rmse_final.get("vel_mps").copied().flatten(),
            pos_rmse_avg_m: f.rmse_time_avg.get("pos_m").copied().flatten(),
            anees: f.consistency.anees,
            min_within_3sigma: f
                .within_3sigma_frac
                .values()
                .flatten()
                .copied()
                .reduce(f64::min),
            diverged: Some(f.diverged),
            us_per_step: Some(f.us_per_step),
            delivery,
            ..self
        }
    }
}

/// The deliveries of `filters` in a cell (`Ok(None)` without `[guidance]`; a failure of the
/// study is the `Err` warning, never the cell's trade results).
pub fn cell_deliveries(
    scenario: &Scenario,
    filters: &[FilterKind],
    runs: usize,
    seed: u64,
) -> Result<Option<Vec<(String, CellDelivery)>>, String> {
    if scenario.config.guidance.is_none() {
        return Ok(None);
    }
    let report = run_delivery(scenario, filters, runs, seed, &|_| {})
        .map_err(|e| format!("cell {}: no delivery: {e}", scenario.config.name))?;
    let Some(perfect) = report.rows.iter().find(|r| r.name == "perfect-nav") else {
        return Ok(None);
    };
    let cell = |r: &DeliveryRow| CellDelivery {
        rms_miss_m: r.rms_miss_m,
        ellipse_99_semi_major_m: r.ellipse_99.map(|e| e.semi_major_m),
        ellipse_99_semi_minor_m: r.ellipse_99.map(|e| e.semi_minor_m),
        failures: r.failures,
        perfect_nav_rms_miss_m: perfect.rms_miss_m,
        perfect_nav_failures: perfect.failures,
    };
    Ok(Some(
        filters
            .iter()
            .filter_map(|k| {
                let r = report.rows.iter().find(|r| r.name == k.name())?;
                Some((k.name().to_string(), cell(r)))
            })
            .collect(),
    ))
}
