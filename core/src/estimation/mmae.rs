//! Multiple-model adaptive estimation (MMAE): model-probability banks and their fusion.
//!
//! A bank runs one filter per hypothesised model (seed 003: one EKF per density bias Δ_i); this
//! module holds the weighting and fusion algebra only. The caller runs the filters and passes
//! each one's innovation log-likelihood ([`gaussian_log_likelihood`]) to [`ClassicBank`]
//! (Magill) or [`MixtureOfExperts`] (seed 003 §3.2, eq. 17–25), then fuses with [`fuse_bank`].
//! Everything works with log-weights and max-subtracted log-sum-exp, so neither tiny likelihoods
//! (the underflow seed 003 §3 blames on Magill's bank) nor large gating activations give NaN.

use super::covariance::{check_covariance, symmetrize};
use super::error::EstimationError;
pub use super::model_probability::gaussian_log_likelihood;
use super::model_probability::{apply_floor, bayes, exp_all, invalid, log_normalise, non_finite};
use nalgebra::{DVector, SMatrix, SVector};

/// Default learning rate η of [`MixtureOfExperts`] (seed 003 eq. 23 does not print its value).
///
/// Per step the gating activation of a consistently best model gains on a rival by about
/// `η (1 − g_best + g_rival) |z|²`. The normalised measurement of seed 003 has `|z|² ≈ 10–100`
/// once dynamic pressure has built up (q/P₀ of a few to ~15, |a|/g₀ of a few), so η = 0.1 takes
/// the best of seven models from the uniform `g = 1/7` to `g > 0.99` in a few tens of steps at
/// most — the "weight quickly tends to 1" of the Δ = 0.095 special case (seed 003 Fig. 5, 8) —
/// while a single step moves `u` by only O(1–10), so one outlier cannot lock the gating.
pub const DEFAULT_ETA: f64 = 0.1;

/// Default probability floor of [`ClassicBank`]: a model can always recover within
/// `ln(1/p_min) ≈ 7` nats of evidence, and the dominant model keeps at least `1 − (n−1)·10⁻³`.
pub const DEFAULT_P_MIN: f64 = 1e-3;

/// Classical (Magill) MMAE: Bayes update of the model probabilities,
/// `p_i(k) = p_i(k−1) N(ε_i; 0, W_i) / Σ_j p_j(k−1) N(ε_j; 0, W_j)`.
///
/// The update is done in log space (`ln p_i + ln N_i`, normalised by log-sum-exp), so it does not
/// underflow even when every likelihood is far below `f64::MIN_POSITIVE`. After normalisation the
/// probabilities are floored at `p_min` (and the rest renormalised): without the floor a model
/// whose probability reaches 0 can never come back (Bayes multiplies by its old probability), the
/// slow-reaction defect seed 003 §3 attributes to Magill's bank. `p_min = 0` disables the floor.
#[derive(Debug, Clone, PartialEq)]
pub struct ClassicBank {
    /// Model probabilities `p_i(k)`, summing to 1.
    pub probs: Vec<f64>,
    /// Probability floor (`0 ≤ p_min < 1/n`); see [`DEFAULT_P_MIN`].
    pub p_min: f64,
}

impl ClassicBank {
    /// Uniform probabilities `1/n` over `n_models ≥ 1` models; requires `0 ≤ p_min < 1/n`.
    pub fn new(n_models: usize, p_min: f64) -> Result<Self, EstimationError> {
        let bank = ClassicBank {
            probs: vec![1.0 / n_models as f64; n_models],
            p_min,
        };
        bank.validate()?;
        Ok(bank)
    }

    fn validate(&self) -> Result<(), EstimationError> {
        let n = self.probs.len();
        if n == 0 {
            return Err(invalid("a model bank needs at least one model"));
        }
        if !(self.p_min >= 0.0 && self.p_min * (n as f64) < 1.0) {
            return Err(invalid(format!(
                "floor p_min = {} not in [0, 1/{n})",
                self.p_min
            )));
        }
        if self.probs.iter().any(|p| !(p.is_finite() && *p >= 0.0)) {
            return Err(invalid("model probabilities must be finite and ≥ 0"));
        }
        Ok(())
    }

    /// One Bayes step with the models' innovation log-likelihoods `ln N(ε_i; 0, W_i)` (e.g. from
    /// [`gaussian_log_likelihood`]); returns the new probabilities. A −∞ log-likelihood (zero
    /// likelihood) is allowed; NaN/+∞ → `NonFinite`; a wrong count or all posteriors zero →
    /// `InvalidInput`. On error the probabilities are left unchanged.
    pub fn update(&mut self, log_likelihoods: &[f64]) -> Result<&[f64], EstimationError> {
        self.validate()?;
        let log_prior: Vec<f64> = self.probs.iter().map(|p| p.ln()).collect();
        let mut post = bayes(&log_prior, log_likelihoods)?;
        apply_floor(&mut post, self.p_min);
        self.probs = post;
        Ok(&self.probs)
    }
}

/// Seed 003's modified mixture of experts (§3.2, eq. 17–25, Fig. 4).
///
/// * Gating (eq. 17–18): `g_i = exp(u_i) / Σ_j exp(u_j)`, `u_i = z_kᵀ a_i`.
/// * Model likelihood (eq. 19): `p_i = N(ε_i; 0, W_i)`, supplied as `ln p_i`.
/// * Mixture likelihood (eq. 20–22): `l = ln Σ_i p_i g_i`.
/// * Posterior (eq. 25): `h_i = p_i g_i / Σ_j p_j g_j`.
/// * Learning (eq. 23–24): `∂l/∂u_i = h_i − g_i`, so `a_i ← a_i + η (h_i − g_i) z_k`.
///
/// **The modification** of seed 003 is that `z_k` is made dimensionless before gating: dynamic
/// pressure / Mars surface pressure, acceleration / g₀, range / R_Mars, range-rate / √(g₀ R_Mars).
/// Raw SI measurements (10⁴ Pa, 10⁶ m) make `u_i` and the learning step enormous. That
/// normalisation is the caller's job; this type takes the normalised vector.
///
/// **Output weights.** The bank's model weights are the posteriors `h_i` (eq. 25, the second
/// value returned by [`MixtureOfExperts::update`]): they include the current measurement, whereas
/// `g_i` is the gating prior computed before it. Pass `h` to [`fuse_bank`].
///
/// **Missing measurement slots.** The normalised vector has a fixed layout (`meas_dim`). For a
/// channel with no measurement this epoch (outage, Electra link not visible) the caller puts 0 in
/// its slot: the slot then adds nothing to `u_i` and its learning increment `η (h_i − g_i)·0`
/// vanishes, so the learned weights of that slot are kept until it returns. The log-likelihoods
/// must be computed over the channels actually available. A step with `z = 0` gates uniformly and
/// learns nothing; `h` is then the likelihood-only posterior.
///
/// Since `Σ_i (h_i − g_i) = 0`, learning leaves `Σ_i a_i` unchanged; the gating is invariant to a
/// common shift of all `a_i`. Everything is computed in log space (`ln p_i + ln g_i`, with
/// `ln g_i = u_i − ln Σ exp u_j`), so large `zᵀa_i` or tiny likelihoods do not give NaN.
#[derive(Debug, Clone, PartialEq)]
pub struct MixtureOfExperts {
    /// Gating weight vectors `a_i`, one per model, each of length `meas_dim`.
    pub a: Vec<DVector<f64>>,
    /// Learning rate η ≥ 0 (eq. 23); see [`DEFAULT_ETA`]. η = 0 freezes the gating.
    pub eta: f64,
}

impl MixtureOfExperts {
    /// `n_models ≥ 1` experts on a `meas_dim ≥ 1` normalised measurement, all `a_i = 0`
    /// (uniform gating `g_i = 1/n`), learning rate `eta` (finite, ≥ 0).
    pub fn new(n_models: usize, meas_dim: usize, eta: f64) -> Result<Self, EstimationError> {
        if n_models == 0 || meas_dim == 0 {
            return Err(invalid(
                "mixture of experts needs ≥ 1 model and measurement",
            ));
        }
        let moe = MixtureOfExperts {
            a: vec![DVector::zeros(meas_dim); n_models],
            eta,
        };
        moe.validate()?;
        Ok(moe)
    }

    fn validate(&self) -> Result<usize, EstimationError> {
        let dim = self.a.first().map(|a| a.len()).unwrap_or(0);
        if dim == 0 || self.a.iter().any(|a| a.len() != dim) {
            return Err(invalid(
                "gating weights a_i must be non-empty and of equal length",
            ));
        }
        if !(self.eta.is_finite() && self.eta >= 0.0) {
            return Err(invalid(format!(
                "learning rate η = {} must be finite and ≥ 0",
                self.eta
            )));
        }
        if self.a.iter().any(|a| a.iter().any(|v| !v.is_finite())) {
            return Err(non_finite("gating weights a_i"));
        }
        Ok(dim)
    }

    /// `ln g_i` (eq. 17) by log-softmax with max subtraction.
    fn log_gating(&self, z: &DVector<f64>) -> Result<Vec<f64>, EstimationError> {
        let dim = self.validate()?;
        if z.len() != dim {
            return Err(invalid(format!(
                "normalised measurement has length {}, expected {dim}",
                z.len()
            )));
        }
        if z.iter().any(|v| !v.is_finite()) {
            return Err(non_finite("normalised measurement z"));
        }
        let u: Vec<f64> = self.a.iter().map(|a| a.dot(z)).collect();
        if u.iter().any(|v| !v.is_finite()) {
            return Err(non_finite("gating activation u_i = zᵀa_i"));
        }
        log_normalise(&u).ok_or_else(|| non_finite("gating activation u_i = zᵀa_i"))
    }

    /// Gating weights `g_i = exp(u_i)/Σ exp(u_j)`, `u_i = z_kᵀ a_i` (eq. 17), by a softmax with
    /// max subtraction; they satisfy eq. 18 (`0 ≤ g_i ≤ 1`, `Σ g_i = 1`).
    pub fn gating(&self, z_normalised: &DVector<f64>) -> Result<Vec<f64>, EstimationError> {
        Ok(exp_all(&self.log_gating(z_normalised)?))
    }

    /// One step: returns (g before learning, h posterior) and learns a_i (eq. 23–25); works in log
    /// space (log p_i + ln g_i) to avoid underflow.
    ///
    /// `log_likelihoods[i] = ln p(z_k | α_i, Z_{k−1})` (eq. 19, e.g. [`gaussian_log_likelihood`]);
    /// −∞ is allowed, NaN/+∞ → `NonFinite`. `h` (eq. 25) are the bank's output weights. On error
    /// the gating weights are left unchanged.
    pub fn update(
        &mut self,
        z_normalised: &DVector<f64>,
        log_likelihoods: &[f64],
    ) -> Result<(Vec<f64>, Vec<f64>), EstimationError> {
        let log_g = self.log_gating(z_normalised)?;
        let h = bayes(&log_g, log_likelihoods)?;
        let g = exp_all(&log_g);
        let a_new: Vec<DVector<f64>> = self
            .a
            .iter()
            .zip(g.iter().zip(&h))
            .map(|(a, (gi, hi))| a + z_normalised * (self.eta * (hi - gi)))
            .collect();
        if a_new.iter().any(|a| a.iter().any(|v| !v.is_finite())) {
            return Err(non_finite("learned gating weights a_i"));
        }
        self.a = a_new;
        Ok((g, h))
    }
}

/// Probability-weighted fusion of the bank's estimates (mean and mixture covariance):
///
/// ```text
/// x̄ = Σ w_i x_i,   P̄ = Σ w_i [P_i + (x_i − x̄)(x_i − x̄)ᵀ]
/// ```
///
/// The spread-of-means term keeps `P̄` honest when the filters disagree (`P̄ ⪰ Σ w_i P_i`).
/// `weights` (e.g. [`ClassicBank::probs`] or the MoE posterior `h`) must be finite and ≥ 0 with a
/// positive sum; they are renormalised to sum to 1. Zero-weight entries are skipped entirely, so
/// a diverged filter whose weight has reached 0 cannot poison the fusion. Errors: length mismatch,
/// empty bank, bad weights → `InvalidInput`; NaN in a weighted estimate → `NonFinite`; fused
/// covariance not positive definite → `NotPositiveDefinite`.
pub fn fuse_bank<const N: usize>(
    weights: &[f64],
    estimates: &[(SVector<f64, N>, SMatrix<f64, N, N>)],
) -> Result<(SVector<f64, N>, SMatrix<f64, N, N>), EstimationError> {
    if weights.len() != estimates.len() || weights.is_empty() {
        return Err(invalid(format!(
            "{} weights for {} estimates",
            weights.len(),
            estimates.len()
        )));
    }
    if weights.iter().any(|w| !(w.is_finite() && *w >= 0.0)) {
        return Err(invalid("fusion weights must be finite and ≥ 0"));
    }
    let total: f64 = weights.iter().sum();
    if !(total > 0.0 && total.is_finite()) {
        return Err(invalid("fusion weights sum to zero"));
    }
    let used: Vec<_> = weights
        .iter()
        .zip(estimates)
        .filter(|(w, _)| **w > 0.0)
        .map(|(w, e)| (w / total, e))
        .collect();
    if used
        .iter()
        .any(|(_, (x, p))| x.iter().chain(p.iter()).any(|v| !v.is_finite()))
    {
        return Err(non_finite("bank estimate or covariance"));
    }
    let mean: SVector<f64, N> = used
        .iter()
        .fold(SVector::zeros(), |acc, (w, (x, _))| acc + x * *w);
    let cov: SMatrix<f64, N, N> = used.iter().fold(SMatrix::zeros(), |acc, (w, (x, p))| {
        let d = x - mean;
        acc + (p + d * d.transpose()) * *w
    });
    let cov = symmetrize(&cov);
    check_covariance(&cov, "fused bank covariance")?;
    Ok((mean, cov))
}
