//! [`TradeError`]: why a trade study (or a study over its runs: the PCRLB, `tune`, a replay)
//! could not run.

use crate::estimation::nav::NavError;
use crate::sim::engine::RunError;
use thiserror::Error;

/// Why a trade study could not run.
#[derive(Debug, Error)]
pub enum TradeError {
    /// Filter selection problem.
    #[error(transparent)]
    Nav(#[from] NavError),
    /// The truth simulation failed (a scenario problem, reported with the run).
    #[error(transparent)]
    Truth(#[from] RunError),
    /// Bad options or shard files.
    #[error("{0}")]
    Options(String),
    /// The scenario gives the filters nothing to measure: every statistic would be empty.
    #[error(
        "scenario '{scenario}' has no measurement channel (no [sensors], or radios without \
         [[beacons]]), so a filter has nothing to navigate with; give [sensors.imu], \
         [sensors.dynamic_pressure], [sensors.heating], or [sensors.range] / \
         [sensors.range_rate] with beacons"
    )]
    NoMeasurements {
        /// The scenario's name.
        scenario: String,
    },
}
