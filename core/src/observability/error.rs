//! [`ObservabilityError`]: why an observability or Fisher-information analysis could not be
//! done.

use thiserror::Error;

/// Why an observability or Fisher-information analysis could not be done.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum ObservabilityError {
    /// The filter state has a dimension the analysis is not compiled for.
    #[error(
        "state dimension {n} is not supported (the analysis handles {} to {} states)",
        crate::state_dim::MIN_STATE_DIM,
        crate::state_dim::MAX_STATE_DIM
    )]
    UnsupportedDimension {
        /// The state dimension.
        n: usize,
    },
    /// The scenario lacks the beacons or channels an analysis needs.
    #[error("scenario '{scenario}' has no {what}")]
    NoBeacons {
        /// Scenario name.
        scenario: String,
        /// What is missing.
        what: String,
    },
    /// A channel's noise 1σ is not positive (needed to scale its rows).
    #[error("channel {channel} has noise 1-sigma {sigma} at t = {t_s} s; it must be positive")]
    BadNoise {
        /// Channel name.
        channel: String,
        /// The offending 1σ.
        sigma: f64,
        /// Time \[s\].
        t_s: f64,
    },
    /// A matrix or state became NaN or infinite.
    #[error("{what} is not finite")]
    NonFinite {
        /// Which quantity (and where).
        what: String,
    },
    /// Inputs that do not fit together or are out of range.
    #[error("invalid input: {0}")]
    InvalidInput(String),
}

impl ObservabilityError {
    /// The same error, located at time `t` \[s\].
    pub fn at(self, t: f64) -> Self {
        match self {
            ObservabilityError::NonFinite { what } => ObservabilityError::NonFinite {
                what: format!("{what} at t = {t} s"),
            },
            ObservabilityError::InvalidInput(m) => {
                ObservabilityError::InvalidInput(format!("{m} (at t = {t} s)"))
            }
            other => other,
        }
    }
}
