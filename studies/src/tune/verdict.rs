//! Whether a tuning may be written: `entrynav tune` checks its own answer on the fresh validation
//! runs, filter by filter, and refuses (unless `--force`) a file that makes any filter worse than
//! the input — fewer epochs inside the NEES band, or a higher time-averaged or final position
//! RMSE, each by more than [`TOLERANCE`] — saying which filter and which figure.

use entrynav::sim::monte_carlo::report::FilterReport;

/// Relative change tolerated before a figure counts as worse (10 %).
pub const TOLERANCE: f64 = 0.10;

/// Every figure on which a filter is worse after the tuning than before (fresh runs).
pub fn worse_figures(before: &[FilterReport], after: &[FilterReport]) -> Vec<String> {
    let mut out = Vec::new();
    for (b, a) in before.iter().zip(after) {
        let band = |r: &FilterReport| r.consistency.nees_in_bounds_frac;
        if let (Some(x), Some(y)) = (band(b), band(a))
            && y < (1.0 - TOLERANCE) * x
        {
            out.push(format!(
                "{}: epochs inside the NEES band {:.1} % -> {:.1} %",
                a.name,
                100.0 * x,
                100.0 * y
            ));
        }
        for (label, pick) in [
            (
                "time-averaged position RMSE",
                rmse_avg as fn(&FilterReport) -> Option<f64>,
            ),
            ("final position RMSE", rmse_final),
        ] {
            if let (Some(x), Some(y)) = (pick(b), pick(a))
                && y > (1.0 + TOLERANCE) * x
            {
                out.push(format!("{}: {label} {x:.4} m -> {y:.4} m", a.name));
            }
        }
    }
    out
}

/// Time-averaged position RMSE \[m\].
pub fn rmse_avg(r: &FilterReport) -> Option<f64> {
    r.rmse_time_avg.get("pos_m").copied().flatten()
}

/// Final position RMSE \[m\].
pub fn rmse_final(r: &FilterReport) -> Option<f64> {
    r.rmse_final.get("pos_m").copied().flatten()
}
