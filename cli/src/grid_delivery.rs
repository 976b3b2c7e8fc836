//! Delivery at deployment in a Monte Carlo grid (`trade --grid`): a cell whose scenario has a
//! `[guidance]` section also flies its runs with each filter in the guidance loop
//! (`entrynav::sim::guided::delivery::run_delivery`, the same run seeds as the cell's trade), and each
//! filter's row carries its RMS miss, 99 % ellipse, failures and perfect navigation's RMS miss
//! on the same runs.

use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::Scenario;
use entrynav::sim::guided::delivery::{DeliveryRow, run_delivery};
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

/// The deliveries of `filters` in a cell (`None` without `[guidance]`; a failure of the study
/// is a warning, never the cell's trade results).
pub fn of_cell(
    scenario: &Scenario,
    filters: &[FilterKind],
    runs: usize,
    seed: u64,
) -> Option<Vec<(String, CellDelivery)>> {
    scenario.config.guidance.as_ref()?;
    let report = run_delivery(scenario, filters, runs, seed, &|_| {})
        .map_err(|e| eprintln!("warning: cell {}: no delivery: {e}", scenario.config.name))
        .ok()?;
    let perfect = report.rows.iter().find(|r| r.name == "perfect-nav")?;
    let cell = |r: &DeliveryRow| CellDelivery {
        rms_miss_m: r.rms_miss_m,
        ellipse_99_semi_major_m: r.ellipse_99.map(|e| e.semi_major_m),
        ellipse_99_semi_minor_m: r.ellipse_99.map(|e| e.semi_minor_m),
        failures: r.failures,
        perfect_nav_rms_miss_m: perfect.rms_miss_m,
        perfect_nav_failures: perfect.failures,
    };
    Some(
        filters
            .iter()
            .filter_map(|k| {
                let r = report.rows.iter().find(|r| r.name == k.name())?;
                Some((k.name().to_string(), cell(r)))
            })
            .collect(),
    )
}
