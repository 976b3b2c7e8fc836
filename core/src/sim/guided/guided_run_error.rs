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

/// Below this altitude a run that stopped before its trigger is counted as a ground impact \[m\]
/// (the engine stops a truth at the surface; a stop higher up is the flight's time limit).
pub const GROUND_IMPACT_ALTITUDE_M: f64 = 100.0;

impl GuidedRunError {
    /// Why the run did not deploy, in a few words a delivery table counts by: "ground impact
    /// before the trigger", "stopped above the ground before the trigger", "navigation filter
    /// failed", or "numerical or setup failure". A failure read back from a shard (`Stored`) is
    /// classified from its message.
    pub fn cause(&self) -> &'static str {
        match self {
            GuidedRunError::NoTrigger { altitude_m, .. } => stop_cause(*altitude_m),
            GuidedRunError::FilterFailed { .. } => "navigation filter failed",
            GuidedRunError::Stored(text) => stored_cause(text),
            // A reference flight's own error (perfect navigation, the unguided bank) says the
            // same in its message.
            other => stored_cause(&other.to_string()),
        }
    }
}

fn stop_cause(altitude_m: f64) -> &'static str {
    if altitude_m <= GROUND_IMPACT_ALTITUDE_M {
        "ground impact before the trigger"
    } else {
        "stopped above the ground before the trigger"
    }
}

/// The cause of a failure stored as its message (the `Display` of the variants above).
fn stored_cause(text: &str) -> &'static str {
    if let Some(rest) = text.split("did not reach the deployment trigger").nth(1) {
        let altitude = rest
            .split("altitude ")
            .nth(1)
            .and_then(|a| a.split(" m").next())
            .and_then(|a| a.trim().parse::<f64>().ok());
        return altitude.map_or("ground impact before the trigger", stop_cause);
    }
    if text.starts_with("the navigation filter failed") {
        return "navigation filter failed";
    }
    "numerical or setup failure"
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn causes_are_the_same_from_the_error_and_from_its_stored_message() {
        for (e, cause) in [
            (
                GuidedRunError::NoTrigger {
                    t_s: 166.0,
                    altitude_m: -2.0,
                    speed_mps: 542.2,
                },
                "ground impact before the trigger",
            ),
            (
                GuidedRunError::NoTrigger {
                    t_s: 400.0,
                    altitude_m: 4000.0,
                    speed_mps: 520.0,
                },
                "stopped above the ground before the trigger",
            ),
            (
                GuidedRunError::FilterFailed {
                    t_s: 12.0,
                    reason: "covariance not positive definite".into(),
                },
                "navigation filter failed",
            ),
        ] {
            assert_eq!(e.cause(), cause);
            assert_eq!(GuidedRunError::Stored(e.to_string()).cause(), cause);
        }
    }
}
