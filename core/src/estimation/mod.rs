//! Navigation filters.
//!
//! The module is layered:
//! * **algorithms** — the estimators themselves on plain vectors and matrices, independent of
//!   Mars entry: [`ekf`] (Joseph-form EKF), `ukf` (scaled unscented filter with the Schmidt
//!   consider form), `ci` (covariance intersection), `mmae` (multiple-model banks);
//! * **navigation filters** — adapters that wire an algorithm to the vehicle's onboard
//!   knowledge ([`Onboard`]: dynamics and measurement models, channels, beacons, tuning), in
//!   `nav`. A filter is built from an `Onboard` value alone and never sees the truth.
//!
//! This layer imports nothing from `scenario` or `sim`: the scenario builds the `Onboard` value,
//! the simulation engine drives the filters and judges them against the truth.
//!
//! Filters never panic on numerical trouble: every step returns a [`EstimationError`] that the
//! caller turns into a filter status.

pub mod adaptive;
pub mod chi_square;
pub mod ci;
mod ci_weights;
pub mod ekf;
pub mod gating;
pub mod mmae;
pub mod nav;
pub mod onboard;
pub mod propagate;
pub mod spd;
pub mod ukf;
pub mod unscented;

pub use onboard::{FilterRetune, FilterTuning, FusionCovariance, Onboard, OnboardChannel};

use crate::math::all_finite;
use nalgebra::SMatrix;
use thiserror::Error;

/// Numerical failure of an estimator step.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum EstimationError {
    /// A covariance (or innovation covariance) is not positive definite.
    #[error("{what} is not positive definite")]
    NotPositiveDefinite {
        /// Which matrix.
        what: String,
    },
    /// A value became NaN or infinite.
    #[error("{what} became non-finite")]
    NonFinite {
        /// Which quantity.
        what: String,
    },
    /// Inputs that do not fit together (lengths, weights, parameters).
    #[error("invalid input: {0}")]
    InvalidInput(String),
}

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
    if spd::cholesky(p).is_none() {
        return Err(EstimationError::NotPositiveDefinite {
            what: what.to_string(),
        });
    }
    Ok(())
}
