//! The exact-covariance `dcifaif` step of the fusion recursion ([`super::fusion`]) along the
//! nominal: every local filter's batch update of the common prior, fused with eq. 21's weights,
//! with the gain-noise term of measured-value noise.

use super::ekf_steps::{failed, noise_slope};
use super::error::EntryLinCovError;
use super::fusion::{Fusion, FusionRecursion, gains_row, sensitivities};
use super::joint::{Joint, block_diagonal, stack};
use super::truth::TruthEpoch;
use crate::estimation::linearization::LinearizedMeasurement;
use crate::estimation::nav::{fuse_exact_with_gains, local_update};
use nalgebra::{DMatrix, SMatrix, SVector};

impl FusionRecursion<'_> {
    /// `dcifaif` with the exact covariance: every local's batch update of the common prior
    /// (`estimation::nav::local_update`), fused with eq. 21's weights; every local is reset to the
    /// result.
    pub(super) fn exact<const N: usize>(
        &self,
        joint: &mut Joint,
        ps: &mut [SMatrix<f64, N, N>],
        xbar: &SVector<f64, N>,
        items: &[LinearizedMeasurement<N>],
        curvature: &[Vec<f64>],
        ep: &TruthEpoch,
    ) -> Result<Fusion<N>, EntryLinCovError> {
        let (members, prior) = (ps.len(), ps[0]);
        let slots: Vec<usize> = ep.meas.iter().map(|m| m.slot).collect();
        let all: Vec<(usize, LinearizedMeasurement<N>)> =
            slots.iter().copied().zip(items.iter().copied()).collect();
        let n_consider = self.onboard.tuning.n_consider;
        let (mut updates, mut who) = (Vec::new(), Vec::new());
        for (i, mask) in self.masks.iter().enumerate() {
            if let Some(u) =
                local_update(xbar, &prior, xbar, &all, mask, n_consider).map_err(failed)?
            {
                updates.push(u);
                who.push(i);
            }
        }
        let mut a = vec![SMatrix::<f64, N, N>::identity(); members];
        let mut g = DMatrix::zeros(N * members, slots.len());
        let mut b = vec![SVector::<f64, N>::zeros(); members];
        for (u, &i) in updates.iter().zip(&who) {
            a[i] = u.a();
            let cols = u
                .gains
                .iter()
                .map(|(slot, _, _)| slots.iter().position(|s| s == slot))
                .collect::<Option<Vec<usize>>>()
                .ok_or_else(|| {
                    EntryLinCovError::Filter("a local used an unknown channel".into())
                })?;
            for ((_, k, _), &col) in u.gains.iter().zip(&cols) {
                g.view_mut((i * N, col), (N, 1)).copy_from(k);
                b[i] += k * (items[col].2 - items[col].0 - curvature[i][col]);
            }
            b[i] += self.batch_gain_noise(joint, i, &prior, items, ep, u.gains.as_slice(), &cols);
        }
        let r_t: Vec<f64> = ep.meas.iter().map(|m| m.r).collect();
        let z_all = sensitivities(ep, self.truth.params.len());
        joint.apply(&block_diagonal(&a), &g, &z_all, &r_t, &stack(&b));
        let (w, p) = match updates.len() {
            0 => (
                gains_row(members, &[0], &[SMatrix::<f64, N, N>::identity()]),
                prior,
            ),
            1 => (
                gains_row(members, &who, &[SMatrix::<f64, N, N>::identity()]),
                updates[0].posterior(&prior),
            ),
            _ => {
                let ((_, p, _), w) = fuse_exact_with_gains(&prior, &updates).map_err(failed)?;
                (gains_row(members, &who, &w), p)
            }
        };
        ps.iter_mut().for_each(|pi| *pi = p);
        Ok((w, p))
    }

    /// E\[ΔK ν\] of a batch gain K = P Hᵀ S⁻¹ whose noise σ is taken from the measured values:
    /// ∂K/∂z_c = −K e_c (S⁻¹)_c,: ∂R_c/∂z_c, and E\[(z_c − z̄_c) ν_d\] = ζ_cᵀζ_d + δ_cd R_t,c −
    /// h_dᵀ E\[δx̂ θᵀ\] ζ_c (the batch form of the EKF's scalar term, [`super::recursion`]).
    #[allow(clippy::too_many_arguments)]
    fn batch_gain_noise<const N: usize>(
        &self,
        joint: &Joint,
        i: usize,
        prior: &SMatrix<f64, N, N>,
        items: &[LinearizedMeasurement<N>],
        ep: &TruthEpoch,
        gains: &[(usize, SVector<f64, N>, f64)],
        cols: &[usize],
    ) -> SVector<f64, N> {
        let slopes: Vec<f64> = gains
            .iter()
            .zip(cols)
            .map(|((slot, _, _), &c)| noise_slope(self.onboard, *slot, items[c].2))
            .collect();
        if slopes.iter().all(|s| *s == 0.0) {
            return SVector::zeros();
        }
        let m = cols.len();
        let s = DMatrix::from_fn(m, m, |a, d| {
            let (ha, hd) = (&items[cols[a]].1, &items[cols[d]].1);
            ha.dot(&(prior * hd)) + if a == d { items[cols[a]].3 } else { 0.0 }
        });
        let Some(s_inv) = s.try_inverse() else {
            return SVector::repeat(f64::NAN);
        };
        let mut out = SVector::<f64, N>::zeros();
        for (a, ((_, k, _), slope)) in gains.iter().zip(&slopes).enumerate() {
            let ma = &ep.meas[cols[a]];
            let cross = joint.cross::<N>(i, &ma.zeta);
            let e: f64 = (0..m)
                .map(|d| {
                    let md = &ep.meas[cols[d]];
                    let cov = ma.zeta.dot(&md.zeta) + if a == d { ma.r } else { 0.0 }
                        - items[cols[d]].1.dot(&cross);
                    s_inv[(a, d)] * cov
                })
                .sum();
            out -= k * (slope * e);
        }
        out
    }
}
