//! [`Fused`]: a fused estimate, its covariance and the fusion weights, and the check every exact
//! fusion applies to it.

use crate::estimation::error::EstimationError;
use crate::estimation::spd::cholesky;
use crate::math::all_finite;
use nalgebra::{SMatrix, SVector};

/// A fused estimate, its covariance and the fusion weights.
pub(crate) type Fused<const N: usize> = (SVector<f64, N>, SMatrix<f64, N, N>, Vec<f64>);

/// A fused estimate, refused when its covariance is not positive definite or its estimate not
/// finite.
pub(super) fn checked<const N: usize>(fused: Fused<N>) -> Result<Fused<N>, EstimationError> {
    if cholesky(&fused.1).is_none() || !all_finite(fused.0.as_slice()) {
        return Err(EstimationError::NotPositiveDefinite {
            what: "the fused covariance".into(),
        });
    }
    Ok(fused)
}
