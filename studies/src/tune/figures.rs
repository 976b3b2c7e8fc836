//! How `tune` writes its figures, in the comment above each tuned table and in the command's
//! printed summary alike.

use entrynav::sim::monte_carlo::report::FilterReport;

/// An objective value with three significant digits (`1.23e-2`).
pub fn sig3(x: f64) -> String {
    format!("{x:.2e}")
}

/// A figure with four decimals, `-` when there is none.
pub fn fmt(v: Option<f64>) -> String {
    v.map(|x| format!("{x:.4}")).unwrap_or_else(|| "-".into())
}

/// ANEES over its degrees of freedom.
pub fn per_dof(r: &FilterReport) -> Option<f64> {
    r.consistency
        .anees
        .map(|a| a / r.consistency.nees_dof.max(1) as f64)
}

/// What J = 0 means for the objective (`--nis-only` or not).
pub fn objective_zero(nis_only: bool) -> &'static str {
    if nis_only {
        "ANIS/dof 1, the NIS inside its band and every channel's NIS/dof 1"
    } else {
        "ANEES/dof and ANIS/dof 1 on average, at every epoch and on every channel"
    }
}

/// The fraction of epochs inside the NEES band, as a percentage, `-` when there is none.
pub fn band(r: &FilterReport) -> String {
    r.consistency
        .nees_in_bounds_frac
        .map_or("-".into(), |f| format!("{:.1} %", 100.0 * f))
}
