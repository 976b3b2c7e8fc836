//! Myers–Tapley process-noise covariance matching (seed 001 eq. 20–21; Myers & Tapley 1976).
//!
//! Over the last `N_b` filter steps (a sliding batch, Myers and Tapley's limited-memory form) the
//! state innovations `qᵢ = x̂ᵢ⁺ − Φ x̂ᵢ₋₁⁺` (eq. 21) and the matrices
//! `Dᵢ = Φ Pᵢ₋₁⁺ Φᵀ − Pᵢ⁺` give
//!
//! ```text
//! Q̂ = 1/(N_b − 1) Σᵢ [ (qᵢ − q̄)(qᵢ − q̄)ᵀ − (N_b − 1)/N_b · Dᵢ ]          (eq. 20)
//! ```
//!
//! For the unscented filter `Φ x̂ᵢ₋₁⁺` is the propagated mean x̂ᵢ⁻ and `Φ Pᵢ₋₁⁺ Φᵀ` the propagated
//! covariance before the process noise is added, `Pᵢ⁻ − Q_{i−1}` (exact for linear dynamics), so
//! `qᵢ = x̂ᵢ⁺ − x̂ᵢ⁻` and `Dᵢ = Pᵢ⁻ − Q_{i−1} − Pᵢ⁺`.
//!
//! Q̂ need not be positive semi-definite. Seed 001 §V.B resets "the diagonal elements ... to the
//! absolute value of their estimates"; we also drop the off-diagonal terms (our reading: a
//! diagonal matrix with non-negative entries is the only form of that reset guaranteed to be a
//! covariance, which the unscented time update needs).

use nalgebra::{SMatrix, SVector};
use std::collections::VecDeque;

/// Sliding-batch Myers–Tapley estimator of the process-noise covariance.
#[derive(Debug, Clone, PartialEq)]
pub struct CovarianceMatching<const N: usize> {
    batch: usize,
    samples: VecDeque<(SVector<f64, N>, SMatrix<f64, N, N>)>,
}

impl<const N: usize> CovarianceMatching<N> {
    /// An estimator over the last `batch` steps (seed 001: 10); `batch` is at least 2.
    pub fn new(batch: usize) -> Self {
        let batch = batch.max(2);
        CovarianceMatching {
            batch,
            samples: VecDeque::with_capacity(batch + 1),
        }
    }

    /// Batch size N_b.
    pub fn batch(&self) -> usize {
        self.batch
    }

    /// Record one step: prior x̂⁻, P⁻, the process noise Q used to form P⁻, posterior x̂⁺, P⁺.
    pub fn push(
        &mut self,
        x_prior: &SVector<f64, N>,
        p_prior: &SMatrix<f64, N, N>,
        q_used: &SMatrix<f64, N, N>,
        x_post: &SVector<f64, N>,
        p_post: &SMatrix<f64, N, N>,
    ) {
        let q = x_post - x_prior;
        let d = p_prior - q_used - p_post;
        self.samples.push_back((q, d));
        while self.samples.len() > self.batch {
            self.samples.pop_front();
        }
    }

    /// Whether a full batch has been recorded.
    pub fn ready(&self) -> bool {
        self.samples.len() == self.batch
    }

    /// Raw eq. 20 over the current batch (None until the batch is full).
    pub fn raw_estimate(&self) -> Option<SMatrix<f64, N, N>> {
        if !self.ready() {
            return None;
        }
        let n = self.batch as f64;
        let mean = self
            .samples
            .iter()
            .fold(SVector::<f64, N>::zeros(), |a, (q, _)| a + q)
            / n;
        let mut qhat = SMatrix::<f64, N, N>::zeros();
        for (q, d) in &self.samples {
            let dq = q - mean;
            qhat.ger(1.0, &dq, &dq, 1.0);
            qhat -= d * ((n - 1.0) / n);
        }
        Some(qhat / (n - 1.0))
    }

    /// The estimate reset to a covariance: `diag(|Q̂ᵢᵢ|)` (see the module documentation).
    pub fn estimate(&self) -> Option<SMatrix<f64, N, N>> {
        self.raw_estimate()
            .map(|q| SMatrix::from_diagonal(&q.diagonal().map(f64::abs)))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_the_innovation_covariance_when_d_is_zero() {
        let mut cm = CovarianceMatching::<2>::new(4);
        let z = SMatrix::<f64, 2, 2>::zeros();
        let xs = [[1.0, 0.0], [-1.0, 0.0], [1.0, 2.0], [-1.0, -2.0]];
        for x in xs {
            cm.push(&SVector::zeros(), &z, &z, &SVector::from(x), &z);
        }
        let q = cm.raw_estimate().unwrap();
        // Sample covariance with mean 0: [[4/3, 4/3], [4/3, 8/3]].
        assert!((q[(0, 0)] - 4.0 / 3.0).abs() < 1e-14);
        assert!((q[(0, 1)] - 4.0 / 3.0).abs() < 1e-14);
        assert!((q[(1, 1)] - 8.0 / 3.0).abs() < 1e-14);
        let e = cm.estimate().unwrap();
        assert_eq!(e[(0, 1)], 0.0);
    }
}
