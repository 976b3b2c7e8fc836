//! What the guidance loop reads besides the estimate: the slots of the accelerometer triad in the
//! onboard channels and its reading in an epoch (the sensed drag), and the truth steps per
//! guidance cycle.

use super::guided_run_error::GuidedRunError;
use crate::estimation::Onboard;
use crate::sensors::{Channel, MeasurementEpoch};

/// Epoch slots of the accelerometer triad in the onboard channel list (`None` without all three:
/// there is no sensed drag for guidance).
pub fn accel_slots(onboard: &Onboard) -> Option<[usize; 3]> {
    let slot = |axis: u8| {
        onboard
            .channels
            .iter()
            .position(|c| c.channel == Channel::Accel(axis))
    };
    Some([slot(0)?, slot(1)?, slot(2)?])
}

/// The accelerometer triad in `epoch` (IMU frame), when all three were read; the sensed drag is
/// `onboard.measurement.imu_frame.drag_from` of it.
pub(super) fn triad(slots: &[usize; 3], epoch: &MeasurementEpoch) -> Option<[f64; 3]> {
    let v = |i: usize| epoch.values.get(slots[i]).copied().flatten();
    Some([v(0)?, v(1)?, v(2)?])
}

/// Truth steps per guidance cycle (an error unless the period is a positive multiple of the step).
pub fn guidance_every(period_s: f64, step_s: f64) -> Result<usize, GuidedRunError> {
    let ratio = period_s / step_s;
    let every = ratio.round() as usize;
    if every == 0 || (ratio - every as f64).abs() > 1e-9 {
        return Err(GuidedRunError::Period { period_s, step_s });
    }
    Ok(every)
}
