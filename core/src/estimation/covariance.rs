//! Covariance hygiene every estimator shares: [`symmetrize`] and [`check_covariance`] (finite
//! and positive definite).

use super::error::EstimationError;
use super::spd::cholesky;
use crate::math::all_finite;
use nalgebra::SMatrix;

/// `(P + Pᵀ)/2`.
pub fn symmetrize<const N: usize>(p: &SMatrix<f64, N, N>) -> SMatrix<f64, N, N> {
    // Entry by entry, without the transposed copy: the same (a + b) · 0.5.
    SMatrix::from_fn(|r, c| (p[(r, c)] + p[(c, r)]) * 0.5)
}

/// Check a covariance is finite and positive definite (Cholesky succeeds).
pub fn check_covariance<const N: usize>(
    p: &SMatrix<f64, N, N>,
    what: &str,
) -> Result<(), EstimationError> {
    if !all_finite(p.as_slice()) {
        return Err(EstimationError::NonFinite {
            what: what.to_string(),
        });
    }
    if cholesky(p).is_none() {
        return Err(EstimationError::NotPositiveDefinite {
            what: what.to_string(),
        });
    }
    Ok(())
}
