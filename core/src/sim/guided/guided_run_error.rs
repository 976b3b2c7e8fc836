//! [`GuidedRunError`]: why a guided run could not be flown or did not reach deployment.

use super::guided_flight::GuidedFlightError;
use crate::guidance::GuidanceError;
use crate::sim::engine::EngineError;
use thiserror::Error;

/// Why a guided run could not be flown or did not reach deployment.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum GuidedRunError {
    /// The scenario has no `[guidance]` section.
    #[error("scenario '{0}' has no [guidance] section: there is nothing to fly in the loop")]
    NoGuidance(String),
    /// The onboard channels lack an accelerometer triad, so there is no sensed drag.
    #[error(
        "scenario '{0}' has no accelerometer triad (accel_x/y/z): guidance needs the sensed drag; \
         give [sensors.imu]"
    )]
    NoAccelerometers(String),
    /// The guidance period is not a positive multiple of the truth step.
    #[error("guidance period {period_s} s is not a positive multiple of the truth step {step_s} s")]
    Period {
        /// Guidance period \[s\].
        period_s: f64,
        /// Truth step \[s\].
        step_s: f64,
    },
    /// The engine failed (filter set-up, non-finite truth).
    #[error(transparent)]
    Engine(#[from] EngineError),
    /// Guidance failed (also: the filter's estimate was not finite).
    #[error(transparent)]
    Guidance(#[from] GuidanceError),
    /// A reference flight (perfect navigation or the unguided bank) failed.
    #[error(transparent)]
    Reference(#[from] GuidedFlightError),
    /// A failure read back from a shard file (`trade --shard`): its message only.
    #[error("{0}")]
    Stored(String),
    /// The filter stopped on a numerical failure before deployment.
    #[error("the navigation filter failed at t = {t_s:.2} s: {reason}")]
    FilterFailed {
        /// Epoch of the failure \[s\].
        t_s: f64,
        /// What failed.
        reason: String,
    },
    /// A [`GuidedLoop`](super::guided_loop::GuidedLoop) was stepped after its run had ended.
    #[error("the guided run has ended ({0}); there is nothing more to step")]
    Ended(String),
    /// The truth stopped (ground, stop speed, duration) before the deployment trigger.
    #[error(
        "the guided truth did not reach the deployment trigger: it stopped at t = {t_s:.2} s, \
         altitude {altitude_m:.0} m, speed {speed_mps:.1} m/s"
    )]
    NoTrigger {
        /// Time \[s\].
        t_s: f64,
        /// Altitude \[m\].
        altitude_m: f64,
        /// Speed \[m/s\].
        speed_mps: f64,
    },
}
