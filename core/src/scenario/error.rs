//! Scenario errors.

use crate::atmosphere::AtmosphereError;
use crate::beacons::BeaconError;
use crate::sensors::SensorError;
use thiserror::Error;

/// Why a scenario could not be read, validated or built.
#[derive(Debug, Error)]
pub enum ScenarioError {
    /// TOML syntax error, unknown field, missing field or malformed number (the message from the
    /// TOML parser carries line and column).
    #[error("{source_name}: {message}")]
    Parse {
        /// File name or `builtin:NAME`.
        source_name: String,
        /// Parser message.
        message: String,
    },
    /// A value outside its physical range.
    #[error("{field} = {value} is out of range: {allowed}")]
    OutOfRange {
        /// Dotted path of the field.
        field: String,
        /// The offending value.
        value: String,
        /// The allowed range, in words.
        allowed: String,
    },
    /// A structural problem (wrong length, missing alternative, inconsistent sections).
    #[error("{field}: {message}")]
    Invalid {
        /// Dotted path of the field.
        field: String,
        /// What is wrong and what is expected.
        message: String,
    },
    /// An initial state no Mars entry has (most likely a unit slip), without
    /// `allow_implausible = true`.
    #[error(
        "{0}; if you mean it, set allow_implausible = true (--set allow_implausible=true, \
         Scenario.set(\"allow_implausible\", True))"
    )]
    Implausible(super::plausibility::Implausible),
    /// No built-in scenario by that name.
    #[error("unknown scenario '{name}': not a built-in ({known}) and not a file")]
    UnknownBuiltin {
        /// Requested name.
        name: String,
        /// Comma-separated built-in names.
        known: String,
    },
    /// Atmosphere description or table problem.
    #[error(transparent)]
    Atmosphere(#[from] AtmosphereError),
    /// Beacon description problem.
    #[error(transparent)]
    Beacon(#[from] BeaconError),
    /// Sensor description problem.
    #[error(transparent)]
    Sensor(#[from] SensorError),
}

impl ScenarioError {
    /// Convenience constructor for [`ScenarioError::OutOfRange`].
    pub fn range(
        field: impl Into<String>,
        value: impl ToString,
        allowed: impl Into<String>,
    ) -> Self {
        ScenarioError::OutOfRange {
            field: field.into(),
            value: value.to_string(),
            allowed: allowed.into(),
        }
    }

    /// Convenience constructor for [`ScenarioError::Invalid`].
    pub fn invalid(field: impl Into<String>, message: impl Into<String>) -> Self {
        ScenarioError::Invalid {
            field: field.into(),
            message: message.into(),
        }
    }
}
