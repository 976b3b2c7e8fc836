//! The exact DCIFAIF fusion in information form (`nav/fusion_exact.rs` has the covariance form
//! and the derivation): every local filter updates the same prior, so its information, its gain
//! on the fused estimate and the fused covariance all follow from the prior's correlation matrix
//! and the channels' rows, with no local covariance formed or inverted.
//!
//! With `D = diag(1/√P_kk)` of the prior `P`, `C = D P D`, the scaled rows `ĥ_c = D⁻¹ h_c` and
//! the scaled local informations `Y'_i = C⁻¹ + Σ_{c ∈ i} ĥ_c ĥ_cᵀ / r_c` ([`PriorInformation`]),
//! the fast CI weights ω_i give `Y' = Σ ω_i Y'_i` and `P_CI = D Y'⁻¹ D`. The local gains are the
//! optimal ones, so `K_i = P⁻H_iᵀ(H_iP⁻H_iᵀ + R_i)⁻¹ = P_i H_iᵀ R_i⁻¹` (multiply
//! `P_i⁻¹ = P⁻⁻¹ + H_iᵀR_i⁻¹H_i` by the first form), and the fused estimate's gain on local `i`
//! maps each of its gain columns to
//!
//! ```text
//! W_i k_ic = ω_i P_CI P_i⁻¹ P_i h_c / r_c = ω_i P_CI h_c / r_c,
//! ```
//!
//! and with `α_c = Σ_{i uses c} ω_i` (the IMU's channels are in every local) the exact fused
//! covariance `B P Bᵀ + Σ_c r_c g_c g_cᵀ` of `fusion_exact.rs` has
//!
//! ```text
//! B = Σ_i W_i A_i = I − Σ_c (α_c / r_c) P_CI h_c h_cᵀ,    g_c = Σ_{i uses c} W_i k_ic = α_c P_CI h_c / r_c
//! ```
//!
//! (using `Σ_i W_i = I`). On the scale `D` that is, with `v_c = Y'⁻¹ ĥ_c`,
//!
//! ```text
//! D P_fused D = B̂ C B̂ᵀ + Σ_c (α_c² / r_c) v_c v_cᵀ,    B̂ = D B D⁻¹ = I − Σ_c (α_c / r_c) v_c ĥ_cᵀ:
//! ```
//!
//! O(N²) per channel and two N × N products, where the covariance form builds the four gains
//! `W_i` (an N × N product each) and `B` from every local's gain columns. The two forms are equal
//! in exact arithmetic; a test checks them against each other to round-off.

use super::fused_estimate::{Fused, checked};
use super::local_update::LocalUpdate;
use crate::estimation::ci::{CiWeighting, fuse_infos};
use crate::estimation::covariance::symmetrize;
use crate::estimation::error::EstimationError;
use crate::estimation::spd::{cholesky, inverse_from_cholesky};
use crate::math::all_finite;
use nalgebra::{SMatrix, SVector};

/// The common prior's information on CI's scale (seed 000 §3.3; [`crate::estimation::ci`]):
/// with `D = diag(1/√P_kk)`, `(D P D)⁻¹ = C⁻¹` for the prior's correlation matrix `C`, which
/// has unit diagonal whatever the units. A Kalman update of that prior with channels `c`
/// (rows `h_c`, noise `r_c`, no consider states) has the posterior information
/// `P_i⁻¹ = P⁻¹ + Σ_c h_c h_cᵀ / r_c` (Maybeck vol. 1 eq. 5-58: the inverse of the Joseph form
/// for the optimal gain of those rows), so on the same scale
/// `Y'_i = (D P_i D)⁻¹ = C⁻¹ + Σ_c (D⁻¹h_c)(D⁻¹h_c)ᵀ / r_c`: one factorisation of the prior per
/// epoch serves every local and every iterated-update pass, instead of one per local and pass.
pub(crate) struct PriorInformation<const N: usize> {
    /// C = D P D.
    c: SMatrix<f64, N, N>,
    /// C⁻¹.
    c_inv: SMatrix<f64, N, N>,
    /// diag(D) = 1/√P_kk.
    pub(super) d: SVector<f64, N>,
}

impl<const N: usize> PriorInformation<N> {
    /// Factor the prior covariance `p`.
    pub fn new(p: &SMatrix<f64, N, N>) -> Result<Self, EstimationError> {
        let not_pd = || EstimationError::NotPositiveDefinite {
            what: "the common prior covariance".into(),
        };
        let d = p.diagonal().map(|v| 1.0 / v.sqrt());
        if d.iter().any(|v| !v.is_finite() || *v <= 0.0) {
            return Err(not_pd());
        }
        let c = SMatrix::<f64, N, N>::from_fn(|r, k| p[(r, k)] * (d[r] * d[k]));
        let chol = cholesky(&symmetrize(&c)).ok_or_else(not_pd)?;
        let c_inv = inverse_from_cholesky(chol.l_dirty());
        if !all_finite(c_inv.as_slice()) {
            return Err(not_pd());
        }
        Ok(PriorInformation { c, c_inv, d })
    }

    /// `Y'_i` of every local update of this prior (none with consider states), exactly
    /// symmetric. The channels every local starts with (the IMU's, first in every local's slot
    /// order) are added to `C⁻¹` once and their sum shared: each entry is still the same sum in
    /// the same order, so every `Y'_i` is the same to the bit.
    pub(super) fn scaled_posterior_informations(
        &self,
        locals: &[LocalUpdate<N>],
    ) -> Vec<SMatrix<f64, N, N>> {
        let slots = |l: &LocalUpdate<N>| l.gains.iter().map(|g| g.0).collect::<Vec<_>>();
        let common = match locals.split_first() {
            Some((first, rest)) => {
                let first = slots(first);
                rest.iter().fold(first.len(), |n, l| {
                    n.min(
                        first
                            .iter()
                            .zip(slots(l))
                            .take_while(|(a, b)| **a == *b)
                            .count(),
                    )
                })
            }
            None => 0,
        };
        // Adds ĥ_c ĥ_cᵀ / r_c of `local`'s channels `from..to` to the upper triangle of `y`.
        let add = |y: &mut SMatrix<f64, N, N>, local: &LocalUpdate<N>, from: usize, to: usize| {
            for ((_, _, r), h) in local.gains[from..to].iter().zip(&local.rows[from..to]) {
                let hs = h.component_div(&self.d);
                for c in 0..N {
                    for k in 0..=c {
                        y[(k, c)] += hs[k] * hs[c] / r;
                    }
                }
            }
        };
        let mut shared = self.c_inv;
        if let Some(first) = locals.first() {
            add(&mut shared, first, 0, common);
        }
        locals
            .iter()
            .map(|l| {
                let mut y = shared;
                add(&mut y, l, common, l.gains.len());
                for c in 0..N {
                    for k in 0..c {
                        y[(c, k)] = y[(k, c)];
                    }
                }
                y
            })
            .collect()
    }
}

/// The fused estimate with fast CI weights and its exact covariance from local updates (none with
/// consider states) of the prior whose information is `info`: `(x̂, P, ω)` (the module doc).
pub(super) fn fuse_information<const N: usize>(
    info: &PriorInformation<N>,
    locals: &[LocalUpdate<N>],
) -> Result<Fused<N>, EstimationError> {
    let ys = info.scaled_posterior_informations(locals);
    let xs: Vec<_> = locals.iter().map(|l| l.x).collect();
    let (ci, yinv) = fuse_infos(&xs, &ys, &info.d, CiWeighting::FastInfNorm)?;
    // Per channel: slot, ĥ_c, r_c and α_c = Σ of the weights of the locals that use it.
    let mut channels: Vec<(usize, SVector<f64, N>, f64, f64)> = Vec::with_capacity(8);
    for (l, w) in locals.iter().zip(&ci.weights) {
        for ((slot, _, r), h) in l.gains.iter().zip(&l.rows) {
            match channels.iter_mut().find(|e| e.0 == *slot) {
                Some(e) => e.3 += w,
                None => channels.push((*slot, h.component_div(&info.d), *r, *w)),
            }
        }
    }
    let mut b = SMatrix::<f64, N, N>::identity();
    let mut noise = SMatrix::<f64, N, N>::zeros();
    for (_, h, r, alpha) in &channels {
        let v = yinv * h;
        b -= v * (h.transpose() * (alpha / r));
        noise += v * (v.transpose() * (alpha * alpha / r));
    }
    let scaled = b * info.c * b.transpose() + noise;
    let fused = symmetrize(&SMatrix::<f64, N, N>::from_fn(|r, k| {
        scaled[(r, k)] / (info.d[r] * info.d[k])
    }));
    checked((ci.x, fused, ci.weights))
}
