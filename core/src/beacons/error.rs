//! [`BeaconError`]: everything that can go wrong when describing or building a beacon, and the
//! input checks that give it.

use crate::planet::Planet;

/// Everything that can go wrong when describing or building a beacon.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum BeaconError {
    /// A quantity is not finite or lies outside its allowed range.
    #[error("{quantity} = {value} is invalid: allowed {allowed}")]
    Invalid {
        /// The quantity or configuration field path, e.g. `beacons[2].circular.altitude_km`.
        quantity: String,
        /// The offending value, formatted with its unit where useful.
        value: String,
        /// The allowed range or form.
        allowed: String,
    },
    /// A configuration gives none, several, or an incomplete set of mutually exclusive alternatives.
    #[error("{field}: {message}")]
    Choice {
        /// The configuration entry, e.g. `beacons[1]`.
        field: String,
        /// What was given and what is expected.
        message: String,
    },
}

impl BeaconError {
    /// Build an [`BeaconError::Invalid`] from anything printable.
    pub(crate) fn invalid(
        quantity: impl Into<String>,
        value: impl std::fmt::Debug,
        allowed: impl Into<String>,
    ) -> Self {
        BeaconError::Invalid {
            quantity: quantity.into(),
            value: format!("{value:?}"),
            allowed: allowed.into(),
        }
    }

    /// Prefix the quantity / field with a configuration path (`"{context}: {quantity}"`).
    pub(crate) fn in_context(self, context: &str) -> Self {
        match self {
            BeaconError::Invalid {
                quantity,
                value,
                allowed,
            } => BeaconError::Invalid {
                quantity: format!("{context}: {quantity}"),
                value,
                allowed,
            },
            BeaconError::Choice { field, message } => BeaconError::Choice {
                field: format!("{context}: {field}"),
                message,
            },
        }
    }
}

/// Reject a non-finite scalar.
pub(crate) fn check_finite(quantity: &str, value: f64) -> Result<(), BeaconError> {
    if value.is_finite() {
        Ok(())
    } else {
        Err(BeaconError::invalid(quantity, value, "a finite number"))
    }
}

/// Reject a vector with a non-finite component.
pub(crate) fn check_finite3(quantity: &str, value: &[f64; 3]) -> Result<(), BeaconError> {
    if value.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(BeaconError::invalid(
            quantity,
            value,
            "three finite components",
        ))
    }
}

/// Reject planet constants the beacon models cannot use (μ ≤ 0, R ≤ 0, non-finite ω).
pub(crate) fn check_planet(planet: &Planet) -> Result<(), BeaconError> {
    if !(planet.mu.is_finite() && planet.mu > 0.0) {
        return Err(BeaconError::invalid(
            "planet.mu [m^3/s^2]",
            planet.mu,
            "finite and > 0",
        ));
    }
    if !(planet.radius.is_finite() && planet.radius > 0.0) {
        return Err(BeaconError::invalid(
            "planet.radius [m]",
            planet.radius,
            "finite and > 0",
        ));
    }
    check_finite("planet.rotation_rate [rad/s]", planet.rotation_rate)
}
