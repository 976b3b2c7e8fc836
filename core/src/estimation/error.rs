//! [`EstimationError`]: the numerical failure of an estimator step, which the caller turns into a
//! filter status (filters never panic on numerical trouble).

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
