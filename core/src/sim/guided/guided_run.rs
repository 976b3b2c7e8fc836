//! One dispersed entry flown with a **navigation filter in the guidance loop** (issue 28): each
//! guidance cycle the filter's estimate — never the truth — becomes the guidance layer's
//! [`NavState`](crate::guidance::NavState), the bank command goes through the [`BankActuator`](crate::guidance::BankActuator) (rate and acceleration
//! limits), and the flown bank drives both the truth and the filter's onboard models.
//!
//! The loop is [`GuidedLoop`] (one truth step per [`GuidedLoop::step`], the code the guided FMU
//! steps too): it drives the engine's step API
//! ([`EntryCoSim::do_step`](crate::sim::engine::EntryCoSim::do_step)) one truth step at a time, so
//! the truth, the sensors and the filter advance exactly as in the FMUs: the bank of step k is
//! the actuator's output after the command computed from the estimate at the start of the step
//! (the epoch at t = k·dt, processed at the end of the previous step). What guidance is given:
//!
//! * the kinematic state of the filter's latest estimate (spherical, or Cartesian converted with
//!   the onboard planet rotation, [`NavState::from_estimate`](crate::guidance::NavState::from_estimate));
//! * the **sensed drag** from the accelerometer triad of the latest measurement epoch, noisy as the
//!   vehicle reads it, rotated from the IMU frame to the wind frame with the onboard IMU frame
//!   ([`crate::sensors::imu::ImuFrame::drag_from`]). A scenario without the three accelerometer
//!   channels cannot be flown this way ([`GuidedRunError::NoAccelerometers`]).
//!
//! Deployment is decided on the truth (true density and airspeed), as in
//! [`super::guided_flight`], and interpolated linearly in the trigger function between the two
//! truth steps around the crossing. A filter failure ends the run as a failure (the vehicle would
//! be flying blind); so does a truth that stops before the trigger.

use super::deployment::Delivery;
use super::guided_loop::{GuidedLoop, GuidedStep};
use super::guided_run_error::GuidedRunError;
use crate::estimation::nav::FilterKind;
use crate::scenario::Scenario;
use std::sync::Arc;

/// Fly Monte Carlo run `run` of a study with master seed `seed` on `scenario` (its `[guidance]`)
/// with filter `kind` in the loop (module documentation). The truth realisation is the trade's
/// for the same (seed, run) ([`EntryCoSim::for_run`](crate::sim::engine::EntryCoSim::for_run)). The result carries the largest bank rate
/// flown, for the caller to hold against the limits ([`within_rate_limit`](super::deployment::within_rate_limit)).
pub fn fly_with_filter(
    scenario: &Arc<Scenario>,
    kind: FilterKind,
    seed: u64,
    run: usize,
) -> Result<Delivery, GuidedRunError> {
    fly_with_filter_recorded(scenario, kind, seed, run, |_| {})
}

/// [`fly_with_filter`], handing every truth step's guidance inputs and flown bank to `record`
/// ([`GuidedStep`]; the guidance FMU's tests replay them).
pub fn fly_with_filter_recorded(
    scenario: &Arc<Scenario>,
    kind: FilterKind,
    seed: u64,
    run: usize,
    mut record: impl FnMut(&GuidedStep),
) -> Result<Delivery, GuidedRunError> {
    let mut flight = GuidedLoop::new(scenario, kind, seed, run)?;
    loop {
        let step = flight.step(&[])?;
        record(&step);
        if let Some(end) = flight.outcome() {
            return end.clone();
        }
    }
}
