//! Errors of the guidance layer.

use thiserror::Error;

/// Why a guidance computation failed.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum GuidanceError {
    /// A guidance parameter is outside its allowed range.
    #[error("guidance parameter {name} = {value} is out of range: {allowed}")]
    Parameter {
        /// Parameter name, as in `[guidance]`.
        name: &'static str,
        /// The value given.
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// The nominal trajectory never met the deployment trigger.
    #[error(
        "the reference trajectory at bank {bank_deg} deg did not reach the deployment trigger \
         within {max_time_s} s (it ended at altitude {altitude_m:.0} m, speed {speed_mps:.1} m/s)"
    )]
    ReferenceNoTrigger {
        /// Reference bank \[deg\].
        bank_deg: f64,
        /// Integration limit \[s\].
        max_time_s: f64,
        /// Altitude where it stopped \[m\].
        altitude_m: f64,
        /// Speed where it stopped \[m/s\].
        speed_mps: f64,
    },
    /// The reference trajectory has too few points after peak speed to tabulate.
    #[error(
        "the reference trajectory has {points} points after its peak speed; at least 3 are needed"
    )]
    ReferenceTooShort {
        /// Points after the peak speed.
        points: usize,
    },
    /// The navigation state handed to guidance is not finite or not physical.
    #[error("navigation state at t = {t_s} s is not usable: {what}")]
    BadNavigation {
        /// Time \[s\].
        t_s: f64,
        /// What is wrong.
        what: &'static str,
    },
}
