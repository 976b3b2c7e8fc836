//! Judging a filter against the truth: the truth in the filter's coordinates, the estimation
//! error, NEES, position and velocity error norms, the deployment (downrange/crossrange) error
//! and the density errors. This is the only code that puts an estimate beside the truth.

use super::truth::TruthSample;
use crate::estimation::spd::cholesky;
use crate::frames::{inertial_to_spherical, spherical_to_fixed, spherical_to_inertial};
use crate::math::wrap_pi;
use crate::scenario::{Scenario, TruthDraw};
use nalgebra::{SMatrix, SVector};

/// The truth of `sample` in the filter model's coordinates, `n` entries: six kinematic states,
/// then the augmented and consider states' truth-equivalent values
/// ([`Scenario::truth_equivalent`]: e.g. a filter ρ0 that absorbs a wrong C_D S/m is judged
/// against ρ0·B_true/B_filter). A state with no truth counterpart (ρ0 when the truth atmosphere
/// is not exponential) is NaN and is reported as unavailable, not as an error.
pub fn truth_in_filter_coords(
    scenario: &Scenario,
    draw: &TruthDraw,
    sample: &TruthSample,
    n: usize,
) -> Vec<f64> {
    let fm = scenario.filter_model();
    let kin = kinematic_truth(scenario, draw, sample);
    let mut x = vec![f64::NAN; n];
    let m = 6.min(n);
    x[..m].copy_from_slice(&kin[..m]);
    for (k, a) in fm.augmented.iter().enumerate() {
        if 6 + k >= n {
            break;
        }
        x[6 + k] = scenario.truth_equivalent(draw, *a).unwrap_or(f64::NAN);
    }
    x
}

/// The six kinematic states of [`truth_in_filter_coords`]: the truth's position and velocity in
/// the filter's coordinates.
pub fn kinematic_truth(scenario: &Scenario, draw: &TruthDraw, sample: &TruthSample) -> [f64; 6] {
    let tm = &draw.model;
    match (
        tm.kind.is_cartesian(),
        scenario.filter_model().kind.is_cartesian(),
    ) {
        (false, false) | (true, true) => sample.state,
        (true, false) => sample.spherical,
        (false, true) => {
            let (p, v) = spherical_to_inertial(&sample.state, sample.t, tm.omega());
            [p[0], p[1], p[2], v[0], v[1], v[2]]
        }
    }
}

/// Estimation error x̂ − x with angles (longitude, heading) wrapped to (−π, π] for spherical states.
pub fn estimation_error<const N: usize>(
    scenario: &Scenario,
    estimate: &SVector<f64, N>,
    truth: &SVector<f64, N>,
) -> SVector<f64, N> {
    let mut e = estimate - truth;
    if !scenario.filter_model().kind.is_cartesian() && N >= 6 {
        e[1] = wrap_pi(e[1]);
        e[5] = wrap_pi(e[5]);
    }
    e
}

/// NEES eᵀP⁻¹e over the states that have a truth value, with its degrees of freedom (`None`
/// when no state has a truth value or that block of P is not positive definite).
///
/// Computed on the correlation matrix, eᵀP⁻¹e = (D⁻¹e)ᵀ(D⁻¹PD⁻¹)⁻¹(D⁻¹e) with D = diag(√P_ii):
/// the states span fifteen orders of magnitude (rad² to m²), and the Cholesky factor of the raw P
/// loses the digits an ill-conditioned but valid covariance needs.
pub fn nees<const N: usize>(
    err: &SVector<f64, N>,
    p: &SMatrix<f64, N, N>,
    truth: &SVector<f64, N>,
) -> Option<(f64, usize)> {
    let idx: Vec<usize> = (0..N).filter(|&i| truth[i].is_finite()).collect();
    let value = scaled_quadratic_form(err, p, &idx)?;
    Some((value, idx.len()))
}

/// eᵀP⁻¹e over the entries `idx` of `e` and `P`, on the correlation matrix (see [`nees`]).
///
/// When `idx` is every state or the six kinematic ones (the two a run judges every epoch) the
/// correlation matrix is fixed-size and factored by [`cholesky`]: the same operations as the
/// general (heap) path, so the same value, without its allocations.
fn scaled_quadratic_form<const N: usize>(
    err: &SVector<f64, N>,
    p: &SMatrix<f64, N, N>,
    idx: &[usize],
) -> Option<f64> {
    let m = idx.len();
    if m == 0 || idx.iter().any(|&i| p[(i, i)].is_nan() || p[(i, i)] <= 0.0) {
        return None;
    }
    let leading = idx.iter().enumerate().all(|(a, &i)| a == i);
    // nalgebra's dot product takes other paths for fixed sizes 2–4: keep those on the heap.
    if leading && m == N && N > 4 {
        return fixed_form::<N, N>(err, p);
    }
    if leading && m == 6 && N >= 6 {
        return fixed_form::<N, 6>(err, p);
    }
    let d: Vec<f64> = idx.iter().map(|&i| p[(i, i)].sqrt()).collect();
    let c = nalgebra::DMatrix::from_fn(m, m, |a, b| p[(idx[a], idx[b])] / (d[a] * d[b]));
    let e = nalgebra::DVector::from_fn(m, |a, _| err[idx[a]] / d[a]);
    let chol = c.cholesky()?;
    Some(e.dot(&chol.solve(&e)))
}

/// [`scaled_quadratic_form`] over the leading `M` states, on fixed-size matrices.
fn fixed_form<const N: usize, const M: usize>(
    err: &SVector<f64, N>,
    p: &SMatrix<f64, N, N>,
) -> Option<f64> {
    let d = SVector::<f64, M>::from_fn(|a, _| p[(a, a)].sqrt());
    let c = SMatrix::<f64, M, M>::from_fn(|a, b| p[(a, b)] / (d[a] * d[b]));
    let e = SVector::<f64, M>::from_fn(|a, _| err[a] / d[a]);
    let chol = cholesky(&c)?;
    Some(e.dot(&chol.solve(&e)))
}

/// NEES over the six kinematic states (the leading 6×6 block of P, on its correlation matrix),
/// `None` if that block is not positive definite.
pub fn nees_kinematic<const N: usize>(
    err: &SVector<f64, N>,
    p: &SMatrix<f64, N, N>,
) -> Option<f64> {
    if N < 6 {
        return None;
    }
    scaled_quadratic_form(err, p, &[0, 1, 2, 3, 4, 5])
}

/// Convert a filter estimate to planet-relative spherical `[r, lon, lat, v, fpa, heading]` at `t`.
pub fn estimate_spherical<const N: usize>(
    scenario: &Scenario,
    x: &SVector<f64, N>,
    t: f64,
) -> [f64; 6] {
    let fm = scenario.filter_model();
    if fm.kind.is_cartesian() {
        inertial_to_spherical(
            &[x[0], x[1], x[2]],
            &[x[3], x[4], x[5]],
            t,
            fm.planet.rotation_rate,
        )
    } else {
        [x[0], x[1], x[2], x[3], x[4], x[5]]
    }
}

/// Position error norm \[m\] and velocity error norm [m/s] of estimate `x` against `truth` (both
/// in filter coordinates; spherical states are compared in the planet-fixed frame).
pub fn pos_vel_error<const N: usize>(
    scenario: &Scenario,
    x: &SVector<f64, N>,
    truth: &SVector<f64, N>,
    err: &SVector<f64, N>,
) -> (f64, f64) {
    if scenario.filter_model().kind.is_cartesian() {
        let e = err;
        (
            (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt(),
            (e[3] * e[3] + e[4] * e[4] + e[5] * e[5]).sqrt(),
        )
    } else {
        let xs: [f64; 6] = [x[0], x[1], x[2], x[3], x[4], x[5]];
        let tr: [f64; 6] = [truth[0], truth[1], truth[2], truth[3], truth[4], truth[5]];
        let (pe, ve) = spherical_to_fixed(&xs);
        let (pt, vt) = spherical_to_fixed(&tr);
        let d = |a: [f64; 3], b: [f64; 3]| {
            ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
        };
        (d(pe, pt), d(ve, vt))
    }
}

/// Downrange/crossrange position error \[m\] of estimate `x` at `t`, in the local horizontal plane
/// at the true position `truth_spherical`, downrange along the true heading.
pub fn downrange_crossrange<const N: usize>(
    scenario: &Scenario,
    x: &SVector<f64, N>,
    t: f64,
    truth_spherical: &[f64; 6],
) -> (f64, f64) {
    let est = estimate_spherical(scenario, x, t);
    let tr = truth_spherical;
    let dn = tr[0] * wrap_pi(est[2] - tr[2]);
    let de = tr[0] * tr[2].cos() * wrap_pi(est[1] - tr[1]);
    let (s, c) = tr[5].sin_cos();
    (dn * c + de * s, -dn * s + de * c)
}
