//! A dual point of the selection relaxation ([`DualPoint`]) and its evaluation on one node
//! (`Scored`: the base and the adjusted scores whose `r` largest give the bound of
//! [`super::bounds`]).

use super::problem::LN_DET_FLOOR;
use nalgebra::Matrix3;

/// A dual point of the relaxation: any such point bounds every node ([`super::bounds`]).
#[derive(Debug, Clone, PartialEq)]
pub enum DualPoint {
    /// D-optimal: `W ≻ 0` (the inverse of a relaxed information matrix) and side-constraint
    /// multipliers `μ ≥ 0`.
    LogDet {
        /// The matrix multiplier `W`.
        w: Matrix3<f64>,
        /// One multiplier per side constraint.
        mu: Vec<f64>,
    },
    /// E-optimal: `Y_e ⪰ 0` per epoch with `Σ tr Y_e = 1`, and multipliers `μ ≥ 0`.
    MinEig {
        /// The PSD multipliers, one per epoch.
        y: Vec<Matrix3<f64>>,
        /// One multiplier per side constraint.
        mu: Vec<f64>,
    },
}

/// `⟨P, Q⟩ = tr(P Q)` of symmetric 3×3 matrices.
pub(super) fn inner(p: &Matrix3<f64>, q: &Matrix3<f64>) -> f64 {
    p.component_mul(q).sum()
}

/// A dual point evaluated on one node: the bound is `finish(base + Σ of the r largest scores)`.
pub(super) struct Scored {
    /// `⟨W, C⟩ + Σ_c μ_c (u_c − |G_c ∩ F|)` (or its E-optimal counterpart).
    pub(super) base: f64,
    /// Adjusted scores of the free sites (same order as `sub.free`).
    pub(super) scores: Vec<f64>,
    /// D-optimal: `ln det W` (the bound is `3 ln(G/3) − ln det W`); E-optimal: `None`.
    pub(super) ln_det_w: Option<f64>,
}

impl Scored {
    pub(super) fn finish(&self, g: f64) -> f64 {
        match self.ln_det_w {
            Some(_) if g <= 0.0 => LN_DET_FLOOR,
            Some(l) => (3.0 * (g / 3.0).ln() - l).max(LN_DET_FLOOR),
            None => g,
        }
    }
}

/// Sum of the `r` largest of `v` (summed in descending order; `v` is reordered).
pub(super) fn top_sum(v: &mut [f64], r: usize) -> f64 {
    let r = r.min(v.len());
    if r == 0 {
        return 0.0;
    }
    v.select_nth_unstable_by(r - 1, |a, b| b.total_cmp(a));
    let top = &mut v[..r];
    top.sort_unstable_by(|a, b| b.total_cmp(a));
    top.iter().sum()
}
