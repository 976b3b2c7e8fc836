//! Observability of the entry navigation system and Fisher information of radio beacons.
//!
//! * [`lie`] — the nonlinear observability matrix O_Σ of seed 002 eq. 12 (seed 000 eq. 11) from
//!   the **exact** Lie derivatives up to order n − 1, by Taylor-mode forward AD over [`Jet`]s
//!   (no symbolic algebra, no finite differences);
//! * [`approx`] — the **quadratic** approximation (seed 002 eq. 13–17) and the **linearised**
//!   matrix (eq. 18–19);
//! * [`degree()`] — δ = σ_min/σ_max by SVD (seed 000 eq. 14, seed 002 eq. 21), its numerical rank,
//!   and the unit scaling: every δ is reported **raw (SI)** and **scaled** (see [`Scaling`]);
//! * [`system`] / [`trajectory`] — the scenario's filter model and channels as an
//!   [`ObservedSystem`], the analysis points on the nominal truth trajectory, and δ(t) for the
//!   centralised system and the IMU + one-beacon subsystems of seed 000 §2.3.3;
//! * [`fisher`] / [`geometry`] — range and range-rate FIM (seed 002 eq. 25, 36, 42–45), det/trace
//!   bounds (eq. 27–28, 37–41), geometry index I (eq. 54), the best N-beacon geometry (Table 1)
//!   and the range FIM along a trajectory;
//!
//! An unobservable configuration (one beacon, rank-deficient O) gives δ = 0 with its rank —
//! never NaN; non-finite inputs are errors ([`ObservabilityError`]).

pub mod approx;
pub mod degree;
pub mod fisher;
pub mod geometry;
pub mod jet;
mod jet_math;
pub mod lie;
pub mod system;
pub mod trajectory;

pub use approx::{linear_matrix, quadratic_matrix};
pub use degree::{Degree, Scaling, degree};
pub use fisher::{FimSummary, geometry_index, max_det_bound};
pub use geometry::{FimEpoch, MaxDet, max_det_directions, range_fim_series};
pub use jet::Jet;
pub use lie::{LieDerivatives, lie_derivatives, lie_matrix};
pub use system::{AnalysisPoint, ObservedSystem, ScenarioSystem, analysis_points};
pub use trajectory::{ChannelSet, DegreeSample, DegreeSeries, DeltaSummary, degree_series};

use nalgebra::{DMatrix, SVector};
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

/// How the observability matrix is computed.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Method {
    /// Exact Lie derivatives up to order n − 1 (seed 002 eq. 12).
    Lie,
    /// Quadratic approximation of the Lie derivatives (seed 002 eq. 13–17).
    Quadratic,
    /// Linearised system (seed 002 eq. 19).
    Linear,
}

impl Method {
    /// Name used on the command line and in reports: `lie`, `quadratic`, `linear`.
    pub fn name(self) -> &'static str {
        match self {
            Method::Lie => "lie",
            Method::Quadratic => "quadratic",
            Method::Linear => "linear",
        }
    }

    /// Parse [`Method::name`].
    /// All methods, in listing order.
    pub const ALL: [Method; 3] = [Method::Lie, Method::Quadratic, Method::Linear];

    /// The method named `name` (the one parser of method names; [`FromStr`](std::str::FromStr)
    /// calls it).
    pub fn from_name(name: &str) -> Option<Method> {
        Method::ALL.into_iter().find(|m| m.name() == name.trim())
    }
}

impl std::str::FromStr for Method {
    type Err = ObservabilityError;

    fn from_str(name: &str) -> Result<Method, ObservabilityError> {
        Method::from_name(name).ok_or_else(|| {
            ObservabilityError::InvalidInput(format!(
                "unknown observability method '{name}'; valid methods are: {}",
                Method::ALL.map(Method::name).join(", ")
            ))
        })
    }
}

/// The observability matrix of `sys` at `x0` by `method`: `(n·m) × n`, rows grouped by Lie
/// order (`k·m + j` is order k of output j).
pub fn observability_matrix<S: ObservedSystem<N>, const N: usize>(
    sys: &S,
    x0: &SVector<f64, N>,
    method: Method,
) -> DMatrix<f64> {
    match method {
        Method::Lie => lie_matrix(sys, x0),
        Method::Quadratic => quadratic_matrix(sys, x0),
        Method::Linear => linear_matrix(sys, x0),
    }
}
