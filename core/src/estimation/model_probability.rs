//! The model-probability algebra of a multiple-model bank ([`super::mmae`]): the innovation
//! log-likelihood, Bayes' rule in log space with max-subtracted log-sum-exp, the probability
//! floor, and the errors a bank reports.

use super::error::EstimationError;
use nalgebra::{DMatrix, DVector};

pub(super) const LN_2PI: f64 = 1.837_877_066_409_345_5;

pub(super) fn invalid(msg: impl Into<String>) -> EstimationError {
    EstimationError::InvalidInput(msg.into())
}

pub(super) fn non_finite(what: &str) -> EstimationError {
    EstimationError::NonFinite { what: what.into() }
}

pub(super) fn not_pd(what: &str) -> EstimationError {
    EstimationError::NotPositiveDefinite { what: what.into() }
}

/// ln N(ε; 0, W) computed stably via Cholesky: −½(εᵀW⁻¹ε + ln det W + m ln 2π).
///
/// This is the log of seed 003 eq. 19, `p(z_k | α_i, Z_{k−1})` with `ε = z_k − h(x̂⁻)` and
/// `W = H P⁻ Hᵀ + R`. The paper prints the normaliser `1/√(2π|W|)`, which is the scalar (m = 1)
/// form; this function uses the correct multivariate density `(2π)^{−m/2} |W|^{−1/2}`. The two
/// differ by the factor `(2π)^{(1−m)/2}`, common to all models that process the same measurement
/// set, so the model weights `h_i` of eq. 25 are unaffected; only the absolute value of eq. 21 is.
///
/// With `W = L Lᵀ` and `y = L⁻¹ ε`, `εᵀW⁻¹ε = |y|²` and `ln det W = 2 Σ ln L_ii`; no
/// exponential is taken, so a huge innovation gives a finite, very negative number. `W` must be
/// symmetric to a relative 1e-8 (it is symmetrised before factorisation). An empty innovation
/// (m = 0, no measurement) returns 0 — the density of "nothing observed" — so a bank step without
/// measurements leaves the model probabilities unchanged.
///
/// Errors: size mismatch, asymmetric `W` → `InvalidInput`; NaN/∞ input or a quadratic form beyond
/// the `f64` range → `NonFinite`; `W` not positive definite → `NotPositiveDefinite`.
pub fn gaussian_log_likelihood(
    innovation: &DVector<f64>,
    w: &DMatrix<f64>,
) -> Result<f64, EstimationError> {
    let m = innovation.len();
    if w.nrows() != m || w.ncols() != m {
        return Err(invalid(format!(
            "innovation length {m}, W {}×{}",
            w.nrows(),
            w.ncols()
        )));
    }
    if innovation.iter().chain(w.iter()).any(|v| !v.is_finite()) {
        return Err(non_finite("innovation or innovation covariance W"));
    }
    if m == 0 {
        return Ok(0.0);
    }
    if (w - w.transpose()).amax() > 1e-8 * w.amax() {
        return Err(invalid("innovation covariance W is not symmetric"));
    }
    let pd = || not_pd("innovation covariance W");
    let chol = (w + w.transpose()).scale(0.5).cholesky().ok_or_else(pd)?;
    let l = chol.l_dirty();
    let y = l.solve_lower_triangular(innovation).ok_or_else(pd)?;
    let quad = y.norm_squared();
    let log_det: f64 = 2.0 * (0..m).map(|i| l[(i, i)].ln()).sum::<f64>();
    let ll = -0.5 * (quad + log_det + m as f64 * LN_2PI);
    if !ll.is_finite() {
        return Err(non_finite("Gaussian log-likelihood"));
    }
    Ok(ll)
}

/// Log-normalise log-weights: `v_i − ln Σ exp v_j` with max subtraction. `None` when every entry
/// is −∞ (all weights zero) or an entry is NaN/+∞.
pub(super) fn log_normalise(v: &[f64]) -> Option<Vec<f64>> {
    let max = v.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if !max.is_finite() || v.iter().any(|x| x.is_nan()) {
        return None;
    }
    let ln_sum = v.iter().map(|x| (x - max).exp()).sum::<f64>().ln();
    Some(v.iter().map(|x| (x - max) - ln_sum).collect())
}

pub(super) fn exp_all(v: &[f64]) -> Vec<f64> {
    v.iter().map(|x| x.exp()).collect()
}

/// Bayes' rule in log space: `post_i ∝ exp(log_prior_i + ll_i)`. The log-likelihoods are first
/// shifted by their maximum, so equal likelihoods of any size leave the prior exactly unchanged.
/// −∞ (zero likelihood) is allowed; NaN/+∞ → `NonFinite`; all posteriors zero → `InvalidInput`.
pub(super) fn bayes(log_prior: &[f64], ll: &[f64]) -> Result<Vec<f64>, EstimationError> {
    if ll.len() != log_prior.len() {
        return Err(invalid(format!(
            "{} log-likelihoods for {} models",
            ll.len(),
            log_prior.len()
        )));
    }
    if ll.iter().any(|l| l.is_nan() || *l == f64::INFINITY) {
        return Err(non_finite("model log-likelihood"));
    }
    let zero = || invalid("every model has zero posterior probability");
    let max = ll.iter().copied().fold(f64::NEG_INFINITY, f64::max);
    if max == f64::NEG_INFINITY {
        return Err(zero());
    }
    let v: Vec<f64> = log_prior
        .iter()
        .zip(ll)
        .map(|(p, l)| p + (l - max))
        .collect();
    Ok(exp_all(&log_normalise(&v).ok_or_else(zero)?))
}

/// Raise every probability below `p_min` to exactly `p_min` and rescale the others so the sum
/// stays 1 ("water filling": rescaling may push further models under the floor, so iterate).
/// `post` must sum to 1 and `n · p_min < 1`; the largest entry is never floored.
pub(super) fn apply_floor(post: &mut [f64], p_min: f64) {
    let mut floored = vec![false; post.len()];
    loop {
        let n_floored = floored.iter().filter(|f| **f).count();
        let free_mass = 1.0 - n_floored as f64 * p_min;
        let free_sum: f64 = post
            .iter()
            .zip(&floored)
            .filter(|(_, f)| !**f)
            .map(|(p, _)| p)
            .sum();
        let factor = free_mass / free_sum;
        let mut changed = false;
        for (p, f) in post.iter().zip(floored.iter_mut()) {
            if !*f && p * factor < p_min {
                *f = true;
                changed = true;
            }
        }
        if !changed {
            for (p, f) in post.iter_mut().zip(&floored) {
                *p = if *f { p_min } else { *p * factor };
            }
            return;
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn log_normalise_handles_extremes() {
        let l = log_normalise(&[-1e300, 0.0, f64::NEG_INFINITY]).unwrap();
        assert_eq!(l[1], 0.0);
        assert_eq!(l[2], f64::NEG_INFINITY);
        assert!(log_normalise(&[f64::NEG_INFINITY; 3]).is_none());
        assert!(log_normalise(&[0.0, f64::NAN]).is_none());
        assert!((log_normalise(&[1e6, 1e6]).unwrap()[0] + std::f64::consts::LN_2).abs() < 1e-12);
    }
}
