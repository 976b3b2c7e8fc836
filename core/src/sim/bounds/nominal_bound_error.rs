//! [`NominalBoundError`]: why the nominal-trajectory bound cannot be formed.

use super::pcrlb::NoBound;
use crate::sim::engine::SimError;
use crate::state_dim::UnsupportedDimension;
use thiserror::Error;

/// Why the nominal bound cannot be formed.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum NominalBoundError {
    /// The scenario has no PCRLB (see [`NoBound`]).
    #[error(transparent)]
    NoBound(#[from] NoBound),
    /// The nominal truth could not be simulated.
    #[error("the nominal truth failed: {0}")]
    Truth(#[from] SimError),
    /// The filter dimension is outside the supported range.
    #[error(transparent)]
    Dimension(#[from] UnsupportedDimension),
    /// The scenario has no range sensor and beacon to give the range epochs.
    #[error("scenario '{0}' has no range channel: give [sensors.range] and at least one beacon")]
    NoRange(String),
    /// Range-rate channels depend on the velocity map, which this bound does not place.
    #[error("scenario '{0}' measures range rate; the nominal bound places range beacons only")]
    RangeRate(String),
    /// A site with a non-finite position, a σ that is not positive or a mask outside [0, π/2).
    #[error(
        "site {index}: position {position:?} m, sigma {sigma} m (finite, sigma > 0, elevation \
         mask in [0, 90) deg)"
    )]
    BadSite {
        /// Site index.
        index: usize,
        /// Its planet-fixed position \[m\].
        position: [f64; 3],
        /// Its range 1σ \[m\].
        sigma: f64,
    },
    /// The recursion lost positive definiteness or produced a non-finite bound.
    #[error("the nominal bound became non-finite at t = {0} s")]
    NonFinite(f64),
}
