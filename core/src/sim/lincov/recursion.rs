//! The augmented-covariance recursion of the entry LinCov for an EKF of dimension N (the
//! equations are in the module documentation of [`super`]).
//!
//! C_θĥ is kept as its p rows c_j = E\[θ_j δx̂\] (N-vectors) and S_k as its columns s_j, so every
//! product is of fixed-size matrices.

use super::second_order::{mean_drift, measurement_bias};
use super::truth::NominalTruth;
use super::{EntryLinCovEpoch, EntryLinCovError};
use crate::estimation::Onboard;
use crate::estimation::nav::{EkfNav, FilterCore, FilterStart};
use crate::frames::spherical_to_fixed;
use crate::math::{dual_gradient, seed_duals};
use crate::scenario::Scenario;
use crate::sim::judge::estimation_error;
use crate::state_dim::DimVisitor;
use nalgebra::{DMatrix, SMatrix, SVector};
use std::sync::Arc;

pub(super) struct Recursion<'a> {
    pub scenario: &'a Scenario,
    pub onboard: &'a Arc<Onboard>,
    pub truth: &'a NominalTruth,
    /// Add the second-order mean drift ([`super::second_order`]).
    pub second_order: bool,
}

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
/// [`crate::sim::judge::nees`]); NaN when that block of P is not positive definite.
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

/// ∂R_f/∂z of the variance the filter assumes for channel `slot` at the measured value `z`
/// (zero for an absolute σ; 2f²z for σ = f|z|).
pub(super) fn noise_slope(onboard: &Onboard, slot: usize, z: f64) -> f64 {
    let Some(spec) = onboard.channels.get(slot) else {
        return 0.0;
    };
    let var = |v: f64| spec.noise.sigma(v).powi(2);
    let dz = 1e-6 * z.abs().max(1e-12);
    (var(z + dz) - var(z - dz)) / (2.0 * dz)
}

pub(super) fn column<const N: usize>(s: &DMatrix<f64>, j: usize) -> SVector<f64, N> {
    SVector::from_fn(|i, _| s[(i, j)])
}

/// `x` with its non-finite entries (no truth counterpart) taken from `fallback`.
pub(super) fn fill<const N: usize>(x: &[f64], fallback: &SVector<f64, N>) -> SVector<f64, N> {
    SVector::from_fn(|i, _| if x[i].is_finite() { x[i] } else { fallback[i] })
}

/// Why the filter failed along the nominal.
pub(super) fn failed(e: crate::estimation::EstimationError) -> EntryLinCovError {
    EntryLinCovError::Filter(e.to_string())
}

/// The start of the recursion: the nominal x̄_0, the filter's start and the moments of its
/// deviation δx̂_0 (the rows c_j = E\[θ_j δx̂_0\], C_ĥĥ and the mean).
pub(super) struct Start<const N: usize> {
    pub xbar: SVector<f64, N>,
    pub filter: FilterStart<N>,
    pub c: Vec<SVector<f64, N>>,
    pub chh: SMatrix<f64, N, N>,
    pub m: SVector<f64, N>,
}

/// x̂_0 drawn around the truth (δx̂_0 = S_0θ + P0^½w) or the fixed nominal start.
pub(super) fn start<const N: usize>(
    sc: &Scenario,
    onboard: &Onboard,
    truth: &NominalTruth,
) -> Start<N> {
    let nominal_start =
        SVector::<f64, N>::from_fn(|i, _| onboard.initial_estimate.get(i).copied().unwrap_or(0.0));
    let xbar = fill(&truth.x0, &nominal_start);
    let filter = FilterStart::<N>::with_estimate(onboard, xbar.as_slice());
    let p_count = truth.params.len();
    let (c, chh, m) = if sc.config.filter.sample_initial_from_p0 {
        let c: Vec<SVector<f64, N>> = (0..p_count).map(|j| column(&truth.s0, j)).collect();
        let chh = c.iter().fold(filter.p0, |acc, s| acc + s * s.transpose());
        (c, chh, SVector::<f64, N>::zeros())
    } else {
        let m0 = estimation_error(sc, &nominal_start, &xbar);
        (vec![SVector::zeros(); p_count], SMatrix::zeros(), m0)
    };
    Start {
        xbar,
        filter,
        c,
        chh,
        m,
    }
}

/// Time update of `navs` (all holding the same estimate, each its own P) to `t` with the
/// filter's own model: every sub-step's mean and Φ from the first, as the EKF and the fusion's
/// shared prediction compute them. Returns the transition Φ over the whole step.
pub(super) fn time_update<const N: usize>(
    navs: &mut [EkfNav<N>],
    t: f64,
) -> Result<SMatrix<f64, N, N>, EntryLinCovError> {
    let mut phi = SMatrix::<f64, N, N>::identity();
    let Some(first) = navs.first() else {
        return Ok(phi);
    };
    let (steps, h, q) = first.substeps_to(t).map_err(failed)?;
    for _ in 0..steps {
        let (x_next, f) = navs[0].substep(h);
        for nav in navs.iter_mut() {
            nav.apply_substep(x_next, &f, &q).map_err(failed)?;
        }
        phi = f * phi;
    }
    for nav in navs.iter_mut() {
        nav.finish_prediction(t);
    }
    Ok(phi)
}

/// The EKF's scalar gain K = P h/(hᵀP h + r_f) with the consider rows zero, and hᵀP h + r_f.
pub(super) fn scalar_gain<const N: usize>(
    p: &SMatrix<f64, N, N>,
    hrow: &SVector<f64, N>,
    r_f: f64,
    n_consider: usize,
    t: f64,
) -> Result<(SVector<f64, N>, f64), EntryLinCovError> {
    let ph = p * hrow;
    let s = hrow.dot(&ph) + r_f;
    if !(s.is_finite() && s > 0.0) {
        return Err(EntryLinCovError::NonFinite {
            what: "innovation variance".into(),
            t,
        });
    }
    let mut k = ph / s;
    for i in N.saturating_sub(n_consider)..N {
        k[i] = 0.0;
    }
    Ok((k, s))
}

impl DimVisitor for Recursion<'_> {
    type Output = Result<Vec<EntryLinCovEpoch>, EntryLinCovError>;

    fn visit<const N: usize, const L: usize>(self) -> Self::Output {
        let (sc, onboard, truth) = (self.scenario, self.onboard, self.truth);
        let spherical = !sc.filter_model().kind.is_cartesian();
        let Start {
            mut xbar,
            filter: start,
            mut c,
            mut chh,
            mut m,
        } = start::<N>(sc, onboard, truth);
        let mut navs = [EkfNav::<N>::new(onboard, &start, None, 1.0).map_err(failed)?];
        let n_consider = onboard.tuning.n_consider;
        let identity = SMatrix::<f64, N, N>::identity();
        let mut p = start.p0;
        let mut out = Vec::with_capacity(truth.epochs.len());
        let mut s_prev = &truth.s0;
        for ep in &truth.epochs {
            // Time update with the filter's own model from the nominal.
            navs[0].set_estimate(xbar, p);
            let second = if self.second_order {
                let moment = chh + m * m.transpose();
                mean_drift(&navs[0], &xbar, &p, ep.t, &[moment], s_prev)?.pop()
            } else {
                None
            };
            s_prev = &ep.s;
            let phi = time_update(&mut navs, ep.t)?;
            let nav = &navs[0];
            let (x_minus, p_minus) = nav.state();
            xbar = fill(&ep.x, &x_minus);
            let drift = estimation_error(sc, &x_minus, &xbar);
            m = phi * m + drift + second.unwrap_or_else(SVector::zeros);
            chh = phi * chh * phi.transpose();
            for cj in c.iter_mut() {
                *cj = phi * *cj;
            }
            // Scalar updates in the EKF's order, linearised at the nominal.
            p = p_minus;
            let beacons = onboard.beacon_states(ep.t);
            let slots: Vec<usize> = ep.meas.iter().map(|z| z.slot).collect();
            let items = nav.items_at(&xbar, &ep.epoch, &beacons, &slots);
            // The iterated update relinearises at its iterate, which takes the prior's
            // measurement curvature out (to the order carried): only the single update has it.
            let curvature = if self.second_order && onboard.tuning.update_iterations <= 1 {
                let moment = chh + m * m.transpose();
                let at = (&ep.epoch, &beacons[..], &slots[..]);
                measurement_bias(nav, &xbar, at, &[moment], &ep.s)?.remove(0)
            } else {
                vec![0.0; items.len()]
            };
            for (((h0, hrow, z, r_f), tm), c2) in items.iter().zip(&ep.meas).zip(&curvature) {
                let (k, s) = scalar_gain(&p, hrow, *r_f, n_consider, ep.t)?;
                let a = identity - k * hrow.transpose();
                let g = c
                    .iter()
                    .zip(tm.zeta.iter())
                    .fold(SVector::<f64, N>::zeros(), |acc, (cj, zj)| acc + cj * *zj);
                // A noise σ the filter takes from the measured value (σ = f|z|) makes its gain
                // correlate with the innovation: E[ΔK ν] = ∂K/∂z E[(z − z̄) ν] with
                // ∂K/∂z = −K (∂R_f/∂z)/s and E[(z − z̄)ν] = ζᵀζ + R_t − H_f g.
                let dr_dz = noise_slope(onboard, tm.slot, *z);
                let gain_noise = k * (-(dr_dz / s) * (tm.zeta.dot(&tm.zeta) + tm.r - hrow.dot(&g)));
                m = a * m + k * (z - h0 - c2) + gain_noise;
                let ag = a * g;
                let zz = tm.zeta.dot(&tm.zeta) + tm.r;
                chh = a * chh * a.transpose()
                    + ag * k.transpose()
                    + k * ag.transpose()
                    + k * k.transpose() * zz;
                for (cj, zj) in c.iter_mut().zip(tm.zeta.iter()) {
                    *cj = a * *cj + k * *zj;
                }
                p = a * p * a.transpose() + k * k.transpose() * *r_f;
            }
            p = (p + p.transpose()) * 0.5;
            out.push(statistics(
                spherical, ep.t, &ep.x, &ep.s, &c, &chh, &m, &p, &xbar,
            )?);
        }
        Ok(out)
    }
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
