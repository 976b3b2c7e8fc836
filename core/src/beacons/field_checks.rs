//! The small checks of a beacon's configuration fields: a finite number in range, three finite
//! components, one of several exclusive alternatives. Errors name the field path.

use super::error::BeaconError;

/// Check `value` is finite and satisfies `ok`.
pub(super) fn check(field: &str, value: f64, ok: bool, allowed: &str) -> Result<(), BeaconError> {
    if value.is_finite() && ok {
        Ok(())
    } else {
        Err(BeaconError::invalid(field, value, allowed))
    }
}

/// Check all three components are finite.
pub(super) fn check3(field: &str, value: &[f64; 3]) -> Result<(), BeaconError> {
    if value.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(BeaconError::invalid(field, value, "three finite numbers"))
    }
}

/// A [`BeaconError::Choice`] for the entry `field`.
pub(super) fn choice(field: &str, message: String) -> BeaconError {
    BeaconError::Choice {
        field: field.to_string(),
        message,
    }
}
