//! Covariance intersection (CI) fusion with information feedback (seed 000 §3.3–3.4).
//!
//! Given `n` estimates `(x̂_i, P_i)` of one state whose cross-covariances are unknown, CI
//! (seed 000 eq. 19–20) fuses them as
//!
//! ```text
//! P_CI = (Σ ω_i P_i⁻¹)⁻¹,   x̂_CI = P_CI Σ ω_i P_i⁻¹ x̂_i,   Σ ω_i = 1, 0 ≤ ω_i ≤ 1,
//! ```
//!
//! which is consistent (`P_CI ⪰ E[(x̂_CI − x)(x̂_CI − x)ᵀ]`) for *every* admissible ω whenever
//! each `P_i` is consistent, whatever the correlations. The weights select the member of that
//! family; [`CiWeighting`] offers the two optimal choices of the paper (minimum trace /
//! determinant of `P_CI`) and its fast ∞-norm rule (eq. 21). [`feedback`] implements the
//! information feedback of eq. 22.
//!
//! **Numerics.** Entry-filter covariances are badly scaled (1e-12 rad² next to 1e6 m²), so
//! information matrices span ~18 orders of magnitude. All inverses use Cholesky, and both the
//! fusion and the weight optimisation run on the similarity-scaled problem `P'_i = D P_i D`,
//! `D = diag(1/√p̄_k)`, `p̄_k = (1/n) Σ_i (P_i)_kk`, which makes every scaled variance O(1).
//! The fused result is mapped back exactly (`P_CI = D⁻¹ P'_CI D⁻¹`).

use super::ci_fast_weights::{fast_weights, fast_weights_scaled};
use super::ci_scaling::{
    Mat, Vect, congruence, invalid, nonfinite, not_pd, scale_from, scaled_infos, spd_inverse,
};
use super::ci_weights::{Weights, optimal_weights};
use super::covariance::symmetrize;
use super::error::EstimationError;
use super::spd::{cholesky, inverse_from_cholesky};
use crate::math::all_finite;
use nalgebra::{SMatrix, SVector};
use serde::{Deserialize, Serialize};

/// Smallest weight [`feedback`] divides by: a local filter with `ω_i < FEEDBACK_WEIGHT_FLOOR`
/// (in particular `ω_i = 0`) is reset to `P_CI / FEEDBACK_WEIGHT_FLOOR` = 10⁶ `P_CI`, i.e. to the
/// fused estimate with a negligible share of its information, instead of an infinite covariance.
pub const FEEDBACK_WEIGHT_FLOOR: f64 = 1e-6;

/// Tolerance on `|Σ ω_i − 1|` accepted by [`ci_fuse`] (the weights are then renormalised).
pub const WEIGHT_SUM_TOLERANCE: f64 = 1e-8;

/// How the CI weights ω are chosen.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
pub enum CiWeighting {
    /// Minimise the *normalised* trace `tr(D P_CI D) = Σ_k (P_CI)_kk / p̄_k` (see the module
    /// doc for `D`, `p̄`), i.e. the sum of fused variances relative to the mean local variances.
    /// The raw trace would be dominated by the m²-sized components; the normalised trace is
    /// dimensionless and invariant to rescaling the state components (changing units).
    OptimalTrace,
    /// Minimise `det P_CI` (equivalently maximise `log det Σ ω_i P_i⁻¹`); invariant to any
    /// invertible linear change of state coordinates.
    OptimalDet,
    /// Seed 000 eq. 21, the closed-form ∞-norm rule (generalised from 4 to `n` estimates).
    /// Computed on the raw (unit-dependent) information matrices, as in the paper.
    FastInfNorm,
}

/// Fused estimate of [`ci_fuse`] / [`covariance_intersection`].
#[derive(Debug, Clone, PartialEq)]
pub struct CiResult<const N: usize> {
    /// Fused estimate x̂_CI (eq. 19).
    pub x: SVector<f64, N>,
    /// Fused covariance P_CI (eq. 20).
    pub p: SMatrix<f64, N, N>,
    /// The weights ω_i used, in input order (non-negative, summing to 1).
    pub weights: Vec<f64>,
}

/// Fusion (eq. 19–20) on the scaled problem; `w` already validated. `chol`, when given, is the
/// Cholesky factor of `Σ ω_i Y'_i` at these weights (the weight search's last factorisation,
/// of the sum as accumulated; the `Y'_i` are exactly symmetric, so it equals the factor of the
/// symmetrised sum formed here without it).
/// Also returns the scaled fused covariance `Y'⁻¹ = (Σ ω_i Y'_i)⁻¹` (for
/// [`covariance_intersection_with_gains`]).
fn fuse_scaled<'a, const N: usize>(
    xs: impl Iterator<Item = &'a Vect<N>>,
    ys: &[Mat<N>],
    s: &Vect<N>,
    (w, chol): Weights<N>,
) -> Result<(CiResult<N>, Mat<N>), EstimationError> {
    let mut y = Mat::<N>::zeros();
    let mut yx = Vect::<N>::zeros();
    for ((wi, yi), xi) in w.iter().zip(ys).zip(xs) {
        if *wi > 0.0 {
            if chol.is_none() {
                y += yi * *wi;
            }
            yx += yi * xi.component_mul(s) * *wi;
        }
    }
    let chol = match chol {
        Some(c) => c,
        None => cholesky(&symmetrize(&y)).ok_or_else(|| not_pd("fused CI information".into()))?,
    };
    let x = chol.solve(&yx).component_div(s);
    let inv_s = s.map(|v| 1.0 / v);
    let yinv = inverse_from_cholesky(chol.l_dirty());
    let p = symmetrize(&congruence(&yinv, &inv_s));
    if !(all_finite(x.as_slice()) && all_finite(p.as_slice())) {
        return Err(nonfinite("fused CI estimate".into()));
    }
    Ok((CiResult { x, p, weights: w }, yinv))
}

/// CI weights ω for information matrices `infos` = `Y_i = P_i⁻¹` (seed 000 §3.3): by minimum
/// (normalised) trace or determinant of `P_CI`, or by the fast ∞-norm rule of eq. 21 (see
/// [`CiWeighting`]). Each `Y_i` must be finite and positive definite; `n = 1` gives `[1]`.
pub fn ci_weights<const N: usize>(
    infos: &[SMatrix<f64, N, N>],
    method: CiWeighting,
) -> Result<Vec<f64>, EstimationError> {
    if infos.is_empty() {
        return invalid("CI needs at least one estimate".into());
    }
    let ps = infos
        .iter()
        .enumerate()
        .map(|(i, y)| spd_inverse(y, || format!("CI information matrix Y_{i}")))
        .collect::<Result<Vec<_>, _>>()?;
    if method == CiWeighting::FastInfNorm {
        let raw: Vec<Mat<N>> = infos.iter().map(symmetrize).collect();
        return fast_weights(&raw);
    }
    let s = scale_from(&ps.iter().map(|p| p.diagonal()).sum(), infos.len())?;
    let inv_s = s.map(|v| 1.0 / v);
    let ys: Vec<Mat<N>> = infos
        .iter()
        .map(|y| symmetrize(&congruence(y, &inv_s)))
        .collect();
    optimal_weights(&ys, method == CiWeighting::OptimalTrace, None).map(|(w, _)| w)
}

/// Fuse `(x̂_i, P_i)` with given weights by seed 000 eq. 19–20. Weights must be finite, in
/// `[0, 1]`, as many as the estimates, and sum to 1 within [`WEIGHT_SUM_TOLERANCE`] (they are
/// renormalised exactly). Every `P_i` must be positive definite, even one with ω_i = 0.
pub fn ci_fuse<const N: usize>(
    estimates: &[(SVector<f64, N>, SMatrix<f64, N, N>)],
    weights: &[f64],
) -> Result<CiResult<N>, EstimationError> {
    let (n, sum) = (estimates.len(), weights.iter().sum::<f64>());
    if weights.len() != n {
        return invalid(format!("{} CI weights for {n} estimates", weights.len()));
    }
    if weights.iter().any(|w| !(0.0..=1.0).contains(w)) {
        return invalid(format!("CI weights must lie in [0, 1]: {weights:?}"));
    }
    if (sum - 1.0).abs() > WEIGHT_SUM_TOLERANCE {
        return invalid(format!("CI weights sum to {sum}, not 1"));
    }
    let (ys, s) = scaled_infos(estimates)?;
    let w = weights.iter().map(|w| w / sum).collect();
    fuse_scaled(estimates.iter().map(|e| &e.0), &ys, &s, (w, None)).map(|(fused, _)| fused)
}

/// Choose the weights by `method` ([`ci_weights`]) and fuse ([`ci_fuse`]), seed 000 eq. 19–21.
pub fn covariance_intersection<const N: usize>(
    estimates: &[(SVector<f64, N>, SMatrix<f64, N, N>)],
    method: CiWeighting,
) -> Result<CiResult<N>, EstimationError> {
    intersect(estimates, method, None).map(|(fused, _)| fused)
}

/// [`covariance_intersection`] whose optimal-weight search (trace or determinant) starts from
/// `start` (e.g. the previous epoch's weights, which change little between epochs) instead of
/// uniform weights. `start` must be as many finite non-negative weights as estimates with a
/// positive sum (it is renormalised); otherwise, or for [`CiWeighting::FastInfNorm`], it is
/// ignored. The optimum is the same to the solver's tolerance (weights to ~1e-7), reached in
/// fewer Newton iterations.
pub fn covariance_intersection_from<const N: usize>(
    estimates: &[(SVector<f64, N>, SMatrix<f64, N, N>)],
    method: CiWeighting,
    start: &[f64],
) -> Result<CiResult<N>, EstimationError> {
    intersect(estimates, method, Some(start)).map(|(fused, _)| fused)
}

/// [`covariance_intersection`] with the gains `W_i = ω_i P_CI P_i⁻¹` of the fused estimate on
/// the local ones (`x̂_CI = Σ W_i x̂_i`, seed 000 eq. 19; `Σ W_i = I`), from the scaled
/// information matrices the fusion already holds: with `Y'_i = (D P_i D)⁻¹` and
/// `Y' = Σ ω_i Y'_i`, `W_i = D⁻¹ (ω_i Y'⁻¹ Y'_i) D` — no further factorisation.
pub fn covariance_intersection_with_gains<const N: usize>(
    estimates: &[(SVector<f64, N>, SMatrix<f64, N, N>)],
    method: CiWeighting,
) -> Result<(CiResult<N>, Vec<SMatrix<f64, N, N>>), EstimationError> {
    let (fused, (ys, s, yinv)) = intersect(estimates, method, None)?;
    let gains = gains_of(&ys, &fused.weights, &s, &yinv);
    Ok((fused, gains))
}

/// [`covariance_intersection_with_gains`] from the scaled information matrices
/// `Y'_i = (D P_i D)⁻¹` and the scale `s = diag(D)` the caller already holds (for instance in
/// information form, `Y'_i = D⁻¹ (P⁻¹ + H_iᵀ R_i⁻¹ H_i) D⁻¹` for Kalman updates of one prior),
/// instead of inverting each `P_i`. `xs` are the estimates x̂_i; every `Y'_i` must be finite,
/// symmetric and positive definite (the fusion's Cholesky factorisation checks their weighted
/// sum).
pub fn covariance_intersection_from_infos<const N: usize>(
    xs: &[SVector<f64, N>],
    ys: &[SMatrix<f64, N, N>],
    s: &SVector<f64, N>,
    method: CiWeighting,
) -> Result<(CiResult<N>, Vec<SMatrix<f64, N, N>>), EstimationError> {
    let (fused, yinv) = fuse_infos(xs, ys, s, method)?;
    let gains = gains_of(ys, &fused.weights, s, &yinv);
    Ok((fused, gains))
}

/// [`covariance_intersection_from_infos`] without the gains, with the inverse `Y'⁻¹` of the
/// weighted scaled information `Y' = Σ ω_i Y'_i` instead (the fused covariance on the scale
/// `s`): for a caller that needs the fused estimate and its covariance only.
pub(crate) fn fuse_infos<const N: usize>(
    xs: &[SVector<f64, N>],
    ys: &[SMatrix<f64, N, N>],
    s: &SVector<f64, N>,
    method: CiWeighting,
) -> Result<(CiResult<N>, SMatrix<f64, N, N>), EstimationError> {
    if xs.is_empty() || xs.len() != ys.len() {
        return invalid(format!(
            "CI of {} estimates with {} informations",
            xs.len(),
            ys.len()
        ));
    }
    if !xs.iter().all(|x| all_finite(x.as_slice()))
        || !ys.iter().all(|y| all_finite(y.as_slice()))
        || s.iter().any(|v| !v.is_finite() || *v <= 0.0)
    {
        return Err(nonfinite("CI estimate, information or scale".into()));
    }
    let w = weights_scaled(ys, s, method, None)?;
    fuse_scaled(xs.iter(), ys, s, w)
}

/// `W_i = D⁻¹ (ω_i Y'⁻¹ Y'_i) D` from the scaled fused covariance `Y'⁻¹`.
fn gains_of<const N: usize>(
    ys: &[Mat<N>],
    weights: &[f64],
    s: &Vect<N>,
    yinv: &Mat<N>,
) -> Vec<Mat<N>> {
    ys.iter()
        .zip(weights)
        .map(|(yi, wi)| {
            let m = yinv * yi * *wi;
            Mat::<N>::from_fn(|r, c| m[(r, c)] * s[c] / s[r])
        })
        .collect()
}

/// The weights of `method` from scaled information matrices (see [`intersect`]).
fn weights_scaled<const N: usize>(
    ys: &[Mat<N>],
    s: &Vect<N>,
    method: CiWeighting,
    start: Option<&[f64]>,
) -> Result<Weights<N>, EstimationError> {
    let start = start.filter(|w| {
        w.len() == ys.len()
            && w.iter().all(|v| v.is_finite() && *v >= 0.0)
            && w.iter().sum::<f64>() > 0.0
    });
    match method {
        CiWeighting::FastInfNorm => fast_weights_scaled(ys, s).map(|w| (w, None)),
        m => optimal_weights(ys, m == CiWeighting::OptimalTrace, start),
    }
}

/// The scaled information matrices, the scale and the scaled fused covariance of a fusion.
type Scaled<const N: usize> = (Vec<Mat<N>>, Vect<N>, Mat<N>);

fn intersect<const N: usize>(
    estimates: &[(SVector<f64, N>, SMatrix<f64, N, N>)],
    method: CiWeighting,
    start: Option<&[f64]>,
) -> Result<(CiResult<N>, Scaled<N>), EstimationError> {
    let (ys, s) = scaled_infos(estimates)?;
    let w = weights_scaled(&ys, &s, method, start)?;
    let (fused, yinv) = fuse_scaled(estimates.iter().map(|e| &e.0), &ys, &s, w)?;
    Ok((fused, (ys, s, yinv)))
}

/// Information feedback, seed 000 eq. 22: each local filter `i` is reset to
/// `x̂⁺_i = x̂_CI`, `P⁺_i = P_CI / ω_i`, so that `Σ_i (P⁺_i)⁻¹ = P_CI⁻¹` (the fused information is
/// shared out, not duplicated). A weight below [`FEEDBACK_WEIGHT_FLOOR`] (including 0, negative
/// or NaN) is replaced by the floor, and one above 1 by 1, so the result is always finite:
/// a filter that received no weight restarts from `x̂_CI` with 10⁶ `P_CI`.
pub fn feedback<const N: usize>(fused: &CiResult<N>) -> Vec<(SVector<f64, N>, SMatrix<f64, N, N>)> {
    fused
        .weights
        .iter()
        .map(|&w| {
            let w = if w.is_nan() {
                FEEDBACK_WEIGHT_FLOOR
            } else {
                w.clamp(FEEDBACK_WEIGHT_FLOOR, 1.0)
            };
            (fused.x, symmetrize(&(fused.p / w)))
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Four badly scaled 11-state posteriors around one truth, like `ci`'s locals, and a fifth
    /// that is the first with 100 times its covariance (dominated: its optimal weight is 0).
    fn estimates() -> Vec<(Vect<11>, Mat<11>)> {
        let mut est: Vec<_> = (0..4)
            .map(|i| {
                let seed = 0.7 + i as f64;
                let a = Mat::<11>::from_fn(|r, c| ((r * 11 + c) as f64 * seed).sin());
                let d = Vect::<11>::from_fn(|r, _| 10f64.powi(r as i32 - 5));
                let p = Mat::<11>::from_fn(|r, c| {
                    (a * a.transpose() + Mat::<11>::identity() * 0.05)[(r, c)] * d[r] * d[c]
                });
                (
                    Vect::<11>::from_fn(|r, _| (r as f64 + seed).cos() * d[r]),
                    p,
                )
            })
            .collect();
        est.push((est[0].0, est[0].1 * 100.0));
        est
    }

    /// The one-pass ∞-norm weights of scaled informations are those of the formed matrices
    /// `S Y'_i S`, bit for bit.
    #[test]
    fn fast_weights_without_forming_the_informations_are_the_same() {
        let est = estimates();
        let (ys, s) = scaled_infos(&est).unwrap();
        let formed: Vec<Mat<11>> = ys.iter().map(|y| congruence(y, &s)).collect();
        let norm = |m: &Mat<11>| m.row_iter().map(|r| r.abs().sum()).fold(0.0, f64::max);
        let y: Mat<11> = formed.iter().sum();
        let num: Vec<f64> = formed
            .iter()
            .map(|yi| (norm(&y) - norm(&(y - yi)) + norm(yi)).max(0.0))
            .collect();
        let den: f64 = num.iter().sum();
        let expected: Vec<f64> = num.iter().map(|v| v / den).collect();
        assert_eq!(fast_weights_scaled(&ys, &s).unwrap(), expected);
        assert_eq!(fast_weights(&formed).unwrap(), expected);
        assert!(expected.iter().all(|w| *w > 0.0 && *w < 1.0));
    }

    #[test]
    fn the_weight_searchs_last_factor_fuses_as_a_fresh_factorisation() {
        let est = estimates();
        let (ys, s) = scaled_infos(&est).unwrap();
        for method in [CiWeighting::OptimalDet, CiWeighting::OptimalTrace] {
            let (w, chol) = weights_scaled(&ys, &s, method, None).unwrap();
            assert!(chol.is_some(), "{method:?}: the search returns its factor");
            // The search sums every Y'_i, the fresh fusion only those with ω_i > 0.
            assert_eq!(
                w[4], 0.0,
                "{method:?}: the dominated estimate gets no weight"
            );
            let xs = || est.iter().map(|e| &e.0);
            let reused = fuse_scaled(xs(), &ys, &s, (w.clone(), chol)).unwrap();
            let fresh = fuse_scaled(xs(), &ys, &s, (w, None)).unwrap();
            assert_eq!(reused, fresh, "{method:?}");
        }
    }
}
