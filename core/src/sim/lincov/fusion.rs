//! LinCov of the CI and DCIFAIF fusion filters ([`crate::estimation::nav::FusionNav`], seed 000
//! §3.3–3.4) along the nominal entry: the recursion of [`super`] on the local filters' stacked
//! deviations ([`super::joint`]), the fused estimate a linear combination of them.
//!
//! Each local filter (the IMU plus one beacon's ranges,
//! [`crate::estimation::nav::fusion_setup::local_masks`]) is an EKF, so along the
//! nominal its deviation δx̂_i obeys the single EKF's linearised recursion with its own P_i and
//! gains (Maybeck vol. 1 ch. 6; Geller 2006, eq. 20–38): δx̂_i⁻ = Φ δx̂_i + d, and per scalar
//! measurement it uses, δx̂_i ← A_i δx̂_i + K_i (ζᵀθ + v + r). The locals share the start, the
//! IMU's noise and θ, so their deviations are correlated; the stacked moments keep those
//! correlations (the cross-covariances covariance intersection assumes unknown).
//!
//! The fused estimate is x̂_CI = P_CI Σ ω_i P_i⁻¹ x̂_i (seed 000 eq. 19–20) = Σ W_i x̂_i with
//! W_i = ω_i P_CI P_i⁻¹ and Σ W_i = I, so δx̂_CI = Σ W_i δx̂_i. The weights ω come from the
//! onboard covariances only (the filter's own code: determinant-optimal for `ci`, eq. 21's fast
//! ∞-norm rule for `dcifaif`), which along the nominal do not depend on the dispersions to first
//! order; so the fusion is linear given the weights.
//!
//! * `ci`: the locals run on their own and are fused after every update; the reported covariance
//!   is P_CI.
//! * `dcifaif`, `fusion_covariance = "paper"`: every local is reset to (x̂_CI, P_CI/ω_i) (eq. 22),
//!   i.e. every block of the stacked deviation to δx̂_CI; the reported covariance is P_CI.
//! * `dcifaif`, `"exact"` (`nav/fusion_exact.rs`): every local makes a batch update of the common
//!   prior, the updates are fused with eq. 21's weights and the exact covariance, which is
//!   reported and fed back.
//!
//! The iterated update (all locals relinearised at the fused iterate for `dcifaif`) is linearised
//! at the nominal, as the EKF's is ([`super`]). Not modelled: a local filter dropped after a
//! numerical failure (along the nominal every local lives, or the LinCov fails) and the innovation
//! gate's exclusions (refused, with the gate).

use super::ekf_steps::{Start, failed, fill, noise_slope, scalar_gain, start, time_update};
use super::epoch::EntryLinCovEpoch;
use super::error::EntryLinCovError;
use super::joint::{Joint, block_diagonal, stack};
use super::second_order::{mean_drift, measurement_bias};
use super::statistics::statistics;
use super::truth::{NominalTruth, TruthEpoch};
use crate::estimation::ci::{covariance_intersection_with_gains, feedback};
use crate::estimation::linearization::LinearizedMeasurement;
use crate::estimation::nav::fusion_setup::{local_start_scale, weighting};
use crate::estimation::nav::{EkfNav, FilterCore};
use crate::estimation::{FusionCovariance, Onboard};
use crate::scenario::Scenario;
use crate::sim::engine::judge::estimation_error;
use crate::state_dim::DimVisitor;
use nalgebra::{DMatrix, SMatrix, SVector};
use std::sync::Arc;

pub(super) struct FusionRecursion<'a> {
    pub scenario: &'a Scenario,
    pub onboard: &'a Arc<Onboard>,
    pub truth: &'a NominalTruth,
    /// Channel slots of each local filter ([`crate::estimation::nav::fusion_setup::local_masks`]).
    pub masks: Vec<Vec<usize>>,
    /// Information feedback (`dcifaif`).
    pub feedback: bool,
    /// Add the second-order mean drift ([`super::second_order`]).
    pub second_order: bool,
}

/// What one fusion step reports: the gains \[W_1 … W_M\] (N × MN) of the fused estimate on the
/// locals' and the fused covariance the filter reports.
pub(super) type Fusion<const N: usize> = (DMatrix<f64>, SMatrix<f64, N, N>);

/// \[W_1 … W_M\] with `w[i]` at the blocks `at[i]` and zero elsewhere.
pub(super) fn gains_row<const N: usize>(
    members: usize,
    at: &[usize],
    w: &[SMatrix<f64, N, N>],
) -> DMatrix<f64> {
    let mut out = DMatrix::zeros(N, N * members);
    for (&i, wi) in at.iter().zip(w) {
        out.view_mut((0, i * N), (N, N)).copy_from(wi);
    }
    out
}

/// The epoch's measurements as (slot, item) pairs and their sensitivities Z (m × p).
pub(super) fn sensitivities(ep: &TruthEpoch, p_count: usize) -> DMatrix<f64> {
    DMatrix::from_fn(ep.meas.len(), p_count, |a, j| ep.meas[a].zeta[j])
}

impl FusionRecursion<'_> {
    /// The locals' scalar updates in the EKF's order (`ci`, and `dcifaif` with the paper's
    /// covariance), each channel applied at once to every local that uses it.
    fn sequential<const N: usize>(
        &self,
        joint: &mut Joint,
        ps: &mut [SMatrix<f64, N, N>],
        items: &[LinearizedMeasurement<N>],
        curvature: &[Vec<f64>],
        ep: &TruthEpoch,
    ) -> Result<(), EntryLinCovError> {
        let members = ps.len();
        let n_consider = self.onboard.tuning.n_consider;
        let z_all = sensitivities(ep, self.truth.params.len());
        for (row, ((h0, hrow, z, r_f), tm)) in items.iter().zip(&ep.meas).enumerate() {
            let dr_dz = noise_slope(self.onboard, tm.slot, *z);
            let zz = tm.zeta.dot(&tm.zeta) + tm.r;
            let mut a = vec![SMatrix::<f64, N, N>::identity(); members];
            let mut g = vec![SVector::<f64, N>::zeros(); members];
            let mut b = vec![SVector::<f64, N>::zeros(); members];
            for i in (0..members).filter(|&i| self.masks[i].contains(&tm.slot)) {
                let (k, s) = scalar_gain(&ps[i], hrow, *r_f, n_consider, ep.t)?;
                // As the EKF's: a σ taken from the measured value correlates gain and innovation.
                let cross = joint.cross::<N>(i, &tm.zeta);
                b[i] =
                    k * (z - h0 - curvature[i][row]) + k * (-(dr_dz / s) * (zz - hrow.dot(&cross)));
                a[i] = SMatrix::identity() - k * hrow.transpose();
                ps[i] = a[i] * ps[i] * a[i].transpose() + k * k.transpose() * *r_f;
                g[i] = k;
            }
            let g = DMatrix::from_column_slice(N * members, 1, stack(&g).as_slice());
            joint.apply(
                &block_diagonal(&a),
                &g,
                &z_all.rows(row, 1).into_owned(),
                &[tm.r],
                &stack(&b),
            );
        }
        for p in ps.iter_mut() {
            *p = (*p + p.transpose()) * 0.5;
        }
        Ok(())
    }

    /// CI of the locals' posteriors with the filter's weights; with feedback (the paper's
    /// `dcifaif`) every local is reset to (x̂_CI, P_CI/ω_i), eq. 22.
    fn intersect<const N: usize>(
        &self,
        xbar: &SVector<f64, N>,
        ps: &mut [SMatrix<f64, N, N>],
    ) -> Result<Fusion<N>, EntryLinCovError> {
        let estimates: Vec<_> = ps.iter().map(|p| (*xbar, *p)).collect();
        let (ci, w) = covariance_intersection_with_gains(&estimates, weighting(self.feedback))
            .map_err(failed)?;
        if self.feedback {
            for (p, (_, reset)) in ps.iter_mut().zip(feedback(&ci)) {
                *p = reset;
            }
        }
        let all: Vec<usize> = (0..ps.len()).collect();
        Ok((gains_row(ps.len(), &all, &w), ci.p))
    }
}

impl DimVisitor for FusionRecursion<'_> {
    type Output = Result<Vec<EntryLinCovEpoch>, EntryLinCovError>;

    fn visit<const N: usize, const L: usize>(self) -> Self::Output {
        let (sc, onboard, truth) = (self.scenario, self.onboard, self.truth);
        let spherical = !sc.filter_model().kind.is_cartesian();
        let Start {
            mut xbar,
            filter: start,
            c,
            chh,
            m,
        } = start::<N>(sc, onboard, truth);
        let members = self.masks.len();
        let exact = self.feedback && onboard.tuning.fusion_covariance == FusionCovariance::Exact;
        let mut local = start.clone();
        local.p0 = start.p0 * local_start_scale(members, self.feedback, exact);
        let mut navs = self
            .masks
            .iter()
            .map(|mask| EkfNav::<N>::new(onboard, &local, Some(mask.clone()), 1.0))
            .collect::<Result<Vec<_>, _>>()
            .map_err(failed)?;
        let mut ps = vec![local.p0; members];
        let mut joint = Joint::replicated(&c, &chh, &m, members);
        let mut out = Vec::with_capacity(truth.epochs.len());
        let mut s_prev = &truth.s0;
        for ep in &truth.epochs {
            // Time update of every local from the nominal with the filter's own model.
            for (nav, p) in navs.iter_mut().zip(&ps) {
                nav.set_estimate(xbar, *p);
            }
            let second = if self.second_order {
                let moments: Vec<_> = (0..members)
                    .map(|i| joint.block_second_moment::<N>(i))
                    .collect();
                Some(mean_drift(&navs[0], &xbar, &ps[0], ep.t, &moments, s_prev)?)
            } else {
                None
            };
            s_prev = &ep.s;
            let phi = time_update(&mut navs, ep.t)?;
            let x_minus = navs[0].state().0;
            for (p, nav) in ps.iter_mut().zip(&navs) {
                *p = nav.state().1;
            }
            xbar = fill(&ep.x, &x_minus);
            let drift = estimation_error(sc, &x_minus, &xbar);
            joint.propagate(&phi, &drift);
            for (i, b) in second.iter().flatten().enumerate() {
                joint.add_mean(i, b);
            }
            let beacons = onboard.beacon_states(ep.t);
            let slots: Vec<usize> = ep.meas.iter().map(|z| z.slot).collect();
            let items = navs[0].items_at(&xbar, &ep.epoch, &beacons, &slots);
            // Only a single (non-iterated) update keeps the prior's measurement curvature.
            let curvature = if self.second_order && onboard.tuning.update_iterations <= 1 {
                let moments: Vec<_> = (0..members)
                    .map(|i| joint.block_second_moment::<N>(i))
                    .collect();
                let at = (&ep.epoch, &beacons[..], &slots[..]);
                measurement_bias(&navs[0], &xbar, at, &moments, &ep.s)?
            } else {
                vec![vec![0.0; items.len()]; members]
            };
            let (w, p_fused) = if exact {
                self.exact(&mut joint, &mut ps, &xbar, &items, &curvature, ep)?
            } else {
                self.sequential(&mut joint, &mut ps, &items, &curvature, ep)?;
                self.intersect(&xbar, &mut ps)?
            };
            let (cf, chh_f, m_f) = joint.combined::<N>(&w);
            if self.feedback {
                // Every local restarts from the fused estimate: X ← (1 ⊗ W) X.
                joint.map(&DMatrix::from_fn(N * members, N * members, |r, col| {
                    w[(r % N, col)]
                }));
            }
            out.push(statistics(
                spherical, ep.t, &ep.x, &ep.s, &cf, &chh_f, &m_f, &p_fused, &xbar,
            )?);
        }
        Ok(out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::estimation::nav::FilterKind;
    use crate::scenario::ScenarioConfig;
    use crate::sim::lincov::recursion::Recursion;
    use crate::sim::lincov::truth::nominal_truth;
    use crate::state_dim::with_state_dim;

    /// One local filter over every channel: the fusion's LinCov (stacked moments, the CI of one
    /// estimate, for `dcifaif` the feedback with the exact covariance's batch update or the
    /// paper's scalar updates) is the EKF's, epoch by epoch. msl-pressure has a consider state, a
    /// relative-noise channel and θ; orbiters-3 a start drawn around the truth. With the
    /// second-order mean drift too.
    #[test]
    fn one_local_filter_is_the_ekf() {
        let (exact, paper) = (FusionCovariance::Exact, FusionCovariance::Paper);
        for (name, feedback, covariance, second_order) in [
            ("msl-pressure", false, exact, false),
            ("msl-pressure", true, paper, false),
            ("orbiters-3", false, exact, false),
            ("orbiters-3", true, exact, false),
            ("orbiters-3", true, paper, false),
            ("msl-pressure", false, exact, true),
            ("orbiters-3", false, exact, true),
        ] {
            let mut cfg = ScenarioConfig::builtin(name).unwrap();
            cfg.filter.fusion_covariance = covariance;
            let s = Scenario::build(cfg, &crate::files::no_files).unwrap();
            let onboard = s.onboard.for_filter(FilterKind::Ekf);
            let n = onboard.state_dim();
            let truth = nominal_truth(&s, n).unwrap();
            let ekf = Recursion {
                scenario: &s,
                onboard: &onboard,
                truth: &truth,
                second_order,
            };
            let ekf = with_state_dim(n, ekf).unwrap().unwrap();
            let one = FusionRecursion {
                scenario: &s,
                onboard: &onboard,
                truth: &truth,
                masks: vec![(0..onboard.channels.len()).collect()],
                feedback,
                second_order,
            };
            let one = with_state_dim(n, one).unwrap().unwrap();
            assert_eq!(one.len(), ekf.len());
            // The paper's feedback re-inverts P every epoch (P_CI/ω of (ωP⁻¹)⁻¹), a round-off
            // that accumulates to ~1e-6 over orbiters-3's 240 epochs.
            let tol = if covariance == paper && feedback {
                1e-5
            } else {
                1e-6
            };
            let close = |a: f64, b: f64| (a - b).abs() <= tol * a.abs().max(b.abs()) + 1e-300;
            for (a, b) in one.iter().zip(&ekf) {
                let pairs = [
                    (a.pos_m, b.pos_m),
                    (a.vel_mps, b.vel_mps),
                    (a.nees, b.nees),
                    (a.pos_sigma_m, b.pos_sigma_m),
                ];
                let states = a
                    .rmse
                    .iter()
                    .zip(&b.rmse)
                    .chain(a.sigma.iter().zip(&b.sigma));
                for (x, y) in pairs.iter().copied().chain(states.map(|(x, y)| (*x, *y))) {
                    assert!(
                        close(x, y) || (x.is_nan() && y.is_nan()),
                        "{name} feedback {feedback} {covariance:?} second order {second_order} \
                         t = {}: {x} vs {y}",
                        a.t
                    );
                }
            }
        }
    }
}
