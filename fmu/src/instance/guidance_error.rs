//! [`GuidanceStepError`]: why the guidance FMU (`MarsEntryGuidance`, [`super::guidance`]) cannot be
//! built, or refuses or fails a step.

use entrynav::guidance::GuidanceError;
use thiserror::Error;

/// Why the guidance FMU cannot be built or refuses or fails a step.
#[derive(Debug, Error)]
pub enum GuidanceStepError {
    /// The scenario has no `[guidance]`.
    #[error(
        "scenario '{0}' has no [guidance] section: the guidance FMU needs one (the default {file} is the built-in msl-guided: msl-airdata with Apollo guidance)",
        file = crate::vars::GUIDED_SCENARIO_FILE
    )]
    NoGuidance(String),
    /// No accelerometer triad among the onboard channels.
    #[error(
        "scenario '{0}' has no accelerometer triad (accel_x/y/z): guidance needs the sensed drag; give [sensors.imu]"
    )]
    NoAccelerometers(String),
    /// The guidance period is not a multiple of the truth step.
    #[error("guidance period {period_s} s is not a positive multiple of the truth step {step_s} s")]
    Period {
        /// Guidance period \[s\].
        period_s: f64,
        /// Truth step \[s\].
        step_s: f64,
    },
    /// Building the guidance or a guidance cycle failed.
    #[error(transparent)]
    Guidance(#[from] GuidanceError),
    /// The navigation filter reports a failure (`nav_status_code` = 2).
    #[error(
        "nav_status_code = 2: the navigation filter failed (at nav_time = {0} s); guidance will not fly its frozen estimate"
    )]
    NavFailed(f64),
    /// The guidance law returned a command that is not finite.
    #[error(
        "the guidance law returned a bank command that is not finite (estimate at nav_time = {0} s)"
    )]
    NonFiniteCommand(f64),
    /// A navigation state outside the bounds guidance accepts.
    #[error(
        "the navigation estimate at nav_time = {t} s is not a state guidance can fly: {what} (connect the navigation FMU's est_x_1..6 and nav_time)"
    )]
    Estimate {
        /// nav_time \[s\].
        t: f64,
        /// What is wrong, with the value and the bound.
        what: String,
    },
}
