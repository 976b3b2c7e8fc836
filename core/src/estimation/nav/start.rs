//! A filter's start: initial estimate, covariance and process noise.

use crate::estimation::onboard::Onboard;
use nalgebra::{SMatrix, SVector};

/// Start of a filter for one run.
#[derive(Debug, Clone, PartialEq)]
pub struct FilterStart<const N: usize> {
    /// Initial estimate.
    pub x0: SVector<f64, N>,
    /// Initial covariance (diagonal `filter.p0_diag`).
    pub p0: SMatrix<f64, N, N>,
    /// Process noise per filter step (diagonal `filter.q_diag`).
    pub q: SMatrix<f64, N, N>,
}

impl<const N: usize> FilterStart<N> {
    /// The onboard start: the nominal initial estimate (`filter.initial`, seed 000 Table 1) with
    /// P0 and Q from the tuning diagonals.
    pub fn nominal(onboard: &Onboard) -> Self {
        Self::with_estimate(onboard, &onboard.initial_estimate)
    }

    /// The start with initial estimate `x0` (missing entries are 0), for example one drawn around
    /// a Monte Carlo run's truth, with P0 and Q from the tuning diagonals (missing P0 entries are
    /// 1, missing Q entries 0).
    pub fn with_estimate(onboard: &Onboard, x0: &[f64]) -> Self {
        let t = &onboard.tuning;
        FilterStart {
            x0: SVector::from_fn(|i, _| x0.get(i).copied().unwrap_or(0.0)),
            p0: SMatrix::from_diagonal(&SVector::from_fn(|i, _| {
                t.p0_diag.get(i).copied().unwrap_or(1.0)
            })),
            q: SMatrix::from_diagonal(&SVector::from_fn(|i, _| {
                t.q_diag.get(i).copied().unwrap_or(0.0)
            })),
        }
    }
}
