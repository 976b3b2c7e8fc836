//! The checks of a communication step every step-wise simulator of the engine makes: that it
//! starts where the previous one ended ([`same_time`]) and has a finite, positive size.

use super::error::EngineError;

/// Whether two communication points are the same instant (relative tolerance 1e-9).
pub fn same_time(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1.0)
}

/// An error unless a step from `t` of size `h` starts at the engine's current `time` and has a
/// finite, positive size.
pub(super) fn check_step(time: f64, t: f64, h: f64) -> Result<(), EngineError> {
    if !t.is_finite() || !same_time(time, t) {
        return Err(EngineError::CommunicationPoint {
            expected: time,
            got: t,
        });
    }
    if !(h.is_finite() && h > 0.0) {
        return Err(EngineError::StepSize(h));
    }
    Ok(())
}
