//! The augmented-covariance recursion of the entry LinCov for an EKF of dimension N (the
//! equations are in the module documentation of [`super`]).
//!
//! C_θĥ is kept as its p rows c_j = E\[θ_j δx̂\] (N-vectors) and S_k as its columns s_j, so every
//! product is of fixed-size matrices.

use super::ekf_steps::{Start, failed, fill, noise_slope, scalar_gain, start, time_update};
use super::epoch::EntryLinCovEpoch;
use super::error::EntryLinCovError;
use super::second_order::{mean_drift, measurement_bias};
use super::statistics::statistics;
use super::truth::NominalTruth;
use crate::estimation::Onboard;
use crate::estimation::nav::{EkfNav, FilterCore};
use crate::scenario::Scenario;
use crate::sim::engine::judge::estimation_error;
use crate::state_dim::DimVisitor;
use nalgebra::{SMatrix, SVector};
use std::sync::Arc;

/// The LinCov of one EKF (the UKF as its EKF equivalent) along the nominal, a [`DimVisitor`]
/// for the filter's dimension.
pub(super) struct Recursion<'a> {
    pub scenario: &'a Scenario,
    pub onboard: &'a Arc<Onboard>,
    pub truth: &'a NominalTruth,
    /// Add the second-order mean drift ([`super::second_order`]).
    pub second_order: bool,
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
