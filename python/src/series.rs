//! A trade's per-epoch series as row-major blocks of f64 (NaN for a missing value), for numpy
//! views without a JSON round trip.

use entrynav::sim::Series;
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;

/// The names [`series`] knows: one value per epoch, or a row per epoch.
const SERIES_KEYS: &str = "times_s, rmse, sigma_mean, bias, pos_rmse_m, local_rmse_m, vel_rmse_mps, \
     nees_mean, nees_kinematic_mean, nis_mean, density_rms_pct, density_mean_pct, \
     density_at_estimate_rms_pct";

/// Rows of possibly missing values as one row-major block, NaN for a missing value or a short
/// row: `(values, rows, columns)`.
fn block(rows: &[Vec<Option<f64>>]) -> (Vec<f64>, usize, usize) {
    let cols = rows.iter().map(Vec::len).max().unwrap_or(0);
    let values = rows
        .iter()
        .flat_map(|r| (0..cols).map(|j| r.get(j).copied().flatten().unwrap_or(f64::NAN)))
        .collect();
    (values, rows.len(), cols)
}

fn column(v: &[Option<f64>]) -> (Vec<f64>, usize, usize) {
    (
        v.iter().map(|x| x.unwrap_or(f64::NAN)).collect(),
        v.len(),
        1,
    )
}

/// Series `key` of `s`: `(values, rows, columns)`.
pub fn series(s: &Series, key: &str) -> PyResult<(Vec<f64>, usize, usize)> {
    Ok(match key {
        "times_s" => (s.times_s.clone(), s.times_s.len(), 1),
        "rmse" => block(&s.rmse),
        "sigma_mean" => block(&s.sigma_mean),
        "bias" => block(&s.bias),
        "local_rmse_m" => block(&s.local_rmse_m),
        "pos_rmse_m" => column(&s.pos_rmse_m),
        "vel_rmse_mps" => column(&s.vel_rmse_mps),
        "nees_mean" => column(&s.nees_mean),
        "nees_kinematic_mean" => column(&s.nees_kinematic_mean),
        "nis_mean" => column(&s.nis_mean),
        "density_rms_pct" => column(&s.density_rms_pct),
        "density_mean_pct" => column(&s.density_mean_pct),
        "density_at_estimate_rms_pct" => column(&s.density_at_estimate_rms_pct),
        _ => {
            return Err(PyValueError::new_err(format!(
                "series '{key}' does not exist: one of {SERIES_KEYS}"
            )));
        }
    })
}
