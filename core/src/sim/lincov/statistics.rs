//! An epoch's predicted statistics from the augmented moments: the RMSE, mean error, σ, position
//! and velocity errors and the NEES a Monte Carlo of the filter would measure.

use super::ekf_steps::column;
use super::epoch::EntryLinCovEpoch;
use super::error::EntryLinCovError;
use crate::frames::spherical_to_fixed;
use crate::math::{dual_gradient, seed_duals};
use nalgebra::{DMatrix, SMatrix, SVector};

/// The position and velocity maps (3×N) at the filter state `x`: Jacobians of the planet-fixed
/// position and velocity for spherical states (the Monte Carlo's `pos_m`, `vel_mps`), the
/// identity blocks for Cartesian ones.
fn maps<const N: usize>(
    spherical: bool,
    x: &SVector<f64, N>,
) -> (SMatrix<f64, 3, N>, SMatrix<f64, 3, N>) {
    let mut jp = SMatrix::<f64, 3, N>::zeros();
    let mut jv = SMatrix::<f64, 3, N>::zeros();
    if spherical {
        let x6 = SVector::<f64, 6>::from_fn(|i, _| x[i]);
        let d = seed_duals(&x6);
        let (pf, vf) = spherical_to_fixed(&[d[0], d[1], d[2], d[3], d[4], d[5]]);
        for i in 0..3 {
            let (gp, gv) = (dual_gradient(&pf[i]), dual_gradient(&vf[i]));
            for j in 0..6 {
                jp[(i, j)] = gp[j];
                jv[(i, j)] = gv[j];
            }
        }
    } else {
        for i in 0..3 {
            jp[(i, i)] = 1.0;
            jv[(i, 3 + i)] = 1.0;
        }
    }
    (jp, jv)
}

/// tr(P⁻¹E) over the entries `idx`, on the correlation scale of P (as the Monte Carlo's NEES,
/// [`crate::sim::engine::judge::nees`]); NaN when that block of P is not positive definite.
fn trace_ratio<const N: usize>(
    p: &SMatrix<f64, N, N>,
    e: &SMatrix<f64, N, N>,
    idx: &[usize],
) -> f64 {
    let m = idx.len();
    let d: Vec<f64> = idx.iter().map(|&i| p[(i, i)].max(0.0).sqrt()).collect();
    if m == 0 || d.iter().any(|v| v.is_nan() || *v <= 0.0) {
        return f64::NAN;
    }
    let c = DMatrix::from_fn(m, m, |a, b| p[(idx[a], idx[b])] / (d[a] * d[b]));
    let s = DMatrix::from_fn(m, m, |a, b| e[(idx[a], idx[b])] / (d[a] * d[b]));
    c.cholesky().map_or(f64::NAN, |ch| ch.solve(&s).trace())
}

/// The epoch's predicted statistics from the augmented moments.
#[allow(clippy::too_many_arguments)]
pub(super) fn statistics<const N: usize>(
    spherical: bool,
    t: f64,
    truth_x: &[f64],
    s: &DMatrix<f64>,
    c: &[SVector<f64, N>],
    chh: &SMatrix<f64, N, N>,
    m: &SVector<f64, N>,
    p: &SMatrix<f64, N, N>,
    xbar: &SVector<f64, N>,
) -> Result<EntryLinCovEpoch, EntryLinCovError> {
    let mut e2 = chh + m * m.transpose();
    for (j, cj) in c.iter().enumerate() {
        let sj = column::<N>(s, j);
        e2 += sj * sj.transpose() - cj * sj.transpose() - sj * cj.transpose();
    }
    let e2 = (e2 + e2.transpose()) * 0.5;
    if e2.iter().chain(p.iter()).any(|v| !v.is_finite()) {
        return Err(EntryLinCovError::NonFinite {
            what: "the augmented covariance".into(),
            t,
        });
    }
    let has = |i: usize| truth_x[i].is_finite();
    let idx: Vec<usize> = (0..N).filter(|&i| has(i)).collect();
    let (jp, jv) = maps(spherical, xbar);
    let root = |v: f64| v.max(0.0).sqrt();
    let kinematic: Vec<usize> = (0..6.min(N)).collect();
    Ok(EntryLinCovEpoch {
        t,
        rmse: (0..N)
            .map(|i| if has(i) { root(e2[(i, i)]) } else { f64::NAN })
            .collect(),
        mean_error: (0..N)
            .map(|i| if has(i) { m[i] } else { f64::NAN })
            .collect(),
        sigma: (0..N).map(|i| root(p[(i, i)])).collect(),
        pos_m: root((jp * e2 * jp.transpose()).trace()),
        vel_mps: root((jv * e2 * jv.transpose()).trace()),
        pos_sigma_m: root((jp * p * jp.transpose()).trace()),
        vel_sigma_mps: root((jv * p * jv.transpose()).trace()),
        nees: trace_ratio(p, &e2, &idx),
        nees_dof: idx.len(),
        nees_kinematic: trace_ratio(p, &e2, &kinematic),
        onboard_cov: p.transpose().iter().copied().collect(),
    })
}
