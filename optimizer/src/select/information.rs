//! The selection's data from a ground-beacon problem: the information blocks of candidate sites
//! and the minimum-spacing side constraints between them.

use super::problem::AtMost;
use crate::error::OptimizerError;
use crate::ground::problem::GroundProblem;
use crate::ground::site::Site;
use entrynav::beacons::ground_visibility_margin;
use entrynav::math::{norm, sub};
use nalgebra::{Matrix3, Vector3};

/// Information blocks of candidate `sites` on `ground`'s trajectory (planet-fixed frame, unit σ):
///
/// * `epoch_step_s = None` — one block per site, the time-averaged FIM
///   `A_i = (1/T) Σ_k w_k n_i(t_k) n_i(t_k)ᵀ` (trace ≤ 1, so `ln det Σ_{i∈S} A_i ≤ 3 ln(k/3)`);
/// * `Some(s)` — the instantaneous `n_i(t) n_i(t)ᵀ` at samples about `s` seconds apart (first and
///   last sample included), for the max-min-over-time E-optimal design.
///
/// Samples where a site does not see the vehicle (eq. 52) contribute nothing.
pub fn site_information(
    ground: &GroundProblem,
    sites: &[Site],
    epoch_step_s: Option<f64>,
) -> Result<Vec<Vec<Matrix3<f64>>>, OptimizerError> {
    let tr = ground.trajectory();
    let fixed = ground.fixed_positions();
    let radius = tr.planet.radius;
    let outer = |b: &[f64; 3], k: usize| -> Matrix3<f64> {
        let v = fixed[k];
        if ground_visibility_margin(b, &v) <= 0.0 {
            return Matrix3::zeros();
        }
        let d = sub(&v, b);
        let u = Vector3::from(d) / norm(&d);
        u * u.transpose()
    };
    let epochs: Option<Vec<usize>> = match epoch_step_s {
        None => None,
        Some(s) => {
            if !(s.is_finite() && s > 0.0) {
                return Err(OptimizerError::InvalidInput(format!(
                    "epoch spacing {s} s must be positive"
                )));
            }
            let mut ks = Vec::new();
            let mut next = tr.times[0];
            for (k, t) in tr.times.iter().enumerate() {
                if *t >= next - 1e-9 {
                    ks.push(k);
                    next = t + s;
                }
            }
            if ks.last() != Some(&(tr.len() - 1)) {
                ks.push(tr.len() - 1);
            }
            Some(ks)
        }
    };
    let duration = tr.duration();
    Ok(sites
        .iter()
        .map(|site| {
            let b = site.fixed_position(radius);
            match &epochs {
                None => vec![(0..tr.len()).fold(Matrix3::zeros(), |acc, k| {
                    acc + outer(&b, k) * (tr.weights[k] / duration)
                })],
                Some(ks) => ks.iter().map(|&k| outer(&b, k)).collect(),
            }
        })
        .collect())
}

/// Minimum spacing between chosen sites as linear side constraints: one [`AtMost`] with `max = 1`
/// (`z_i + z_j ≤ 1` in the relaxation) for every pair of `sites` closer than `min_angle_rad`
/// (great-circle angle between the site directions). Pairs are listed in ascending order.
pub fn separation_constraints(
    sites: &[Site],
    min_angle_rad: f64,
) -> Result<Vec<AtMost>, OptimizerError> {
    if !(min_angle_rad.is_finite() && min_angle_rad >= 0.0) {
        return Err(OptimizerError::InvalidInput(format!(
            "minimum site separation {min_angle_rad} rad must be finite and non-negative"
        )));
    }
    let dirs: Vec<Vector3<f64>> = sites
        .iter()
        .map(|s| Vector3::from(s.fixed_position(1.0)).normalize())
        .collect();
    let mut out = Vec::new();
    for i in 0..dirs.len() {
        for j in i + 1..dirs.len() {
            let angle = dirs[i].cross(&dirs[j]).norm().atan2(dirs[i].dot(&dirs[j]));
            if angle < min_angle_rad {
                out.push(AtMost {
                    sites: vec![i, j],
                    max: 1,
                });
            }
        }
    }
    Ok(out)
}
