//! One dispersed entry flown with a **navigation filter in the guidance loop** (issue 28): each
//! guidance cycle the filter's estimate — never the truth — becomes the guidance layer's
//! [`NavState`](crate::guidance::NavState), the bank command goes through the [`BankActuator`](crate::guidance::BankActuator) (rate and acceleration
//! limits), and the flown bank drives both the truth and the filter's onboard models.
//!
//! The loop is [`GuidedLoop`] (one truth step per [`GuidedLoop::step`], the code the guided FMU
//! steps too): it drives the engine's step API
//! ([`EntryCoSim::do_step`](super::engine::EntryCoSim::do_step)) one truth step at a time, so
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

use super::engine::{EngineError, TruthSample};
use super::guided_flight::GuidedFlight;
pub use super::guided_loop::{GuidedLoop, GuidedStep};
use crate::estimation::Onboard;
use crate::estimation::nav::FilterKind;
use crate::guidance::{BankLimits, GuidanceError, Target, Trigger, bearing, central_angle};
use crate::scenario::Scenario;
use crate::sensors::{Channel, MeasurementEpoch};
use serde::{Deserialize, Serialize};
use std::sync::Arc;
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
    Reference(#[from] super::guided_flight::GuidedFlightError),
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
    /// A [`GuidedLoop`] was stepped after its run had ended.
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

/// The navigation error at deployment: the filter's latest estimate (the last measurement epoch
/// at or before the trigger) against the truth at that epoch.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DeployNavError {
    /// Position error norm \[m\].
    pub position_m: f64,
    /// Velocity error norm \[m/s\].
    pub velocity_mps: f64,
    /// Downrange (along the true heading) position error \[m\].
    pub downrange_m: f64,
    /// Crossrange position error \[m\].
    pub crossrange_m: f64,
}

/// Where one flight deployed and how far from the target.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Delivery {
    /// Deployment time \[s\].
    pub t_deploy_s: f64,
    /// Deployment latitude \[deg\].
    pub lat_deg: f64,
    /// Deployment longitude \[deg\].
    pub lon_deg: f64,
    /// Deployment altitude \[m\].
    pub altitude_m: f64,
    /// Surface distance from the deployment point to the target \[m\].
    pub miss_m: f64,
    /// Along-track part of the miss, positive when the vehicle overflew the target \[m\].
    pub downrange_m: f64,
    /// Cross-track part of the miss, positive when the target lies to the right \[m\].
    pub crossrange_m: f64,
    /// Largest |bank rate| flown over any truth step \[deg/s\].
    pub max_bank_rate_deg_s: f64,
    /// Navigation error at deployment (`None` for perfect navigation and the unguided flight).
    pub nav_error: Option<DeployNavError>,
}

impl Delivery {
    /// The delivery of a flight of [`super::guided_flight`] (perfect navigation or a constant
    /// bank), with the largest bank rate over its samples.
    pub fn from_flight(f: &GuidedFlight) -> Delivery {
        let max_rate = f
            .samples
            .windows(2)
            .map(|w| (w[1].bank - w[0].bank).abs() / (w[1].t - w[0].t))
            .fold(0.0, f64::max);
        Delivery {
            t_deploy_s: f.t_deploy,
            lat_deg: f.deploy_lat_lon[0].to_degrees(),
            lon_deg: f.deploy_lat_lon[1].to_degrees(),
            altitude_m: f.deploy_altitude_m,
            miss_m: f.miss_m,
            downrange_m: f.downrange_error_m,
            crossrange_m: f.crossrange_error_m,
            max_bank_rate_deg_s: max_rate.to_degrees(),
            nav_error: None,
        }
    }
}

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

/// The trigger function on a truth sample (airspeed from the dynamic pressure, so it is the
/// planet-relative air speed on a rotating planet too).
pub(super) fn trigger_on(trigger: &Trigger, s: &TruthSample) -> f64 {
    let airspeed = if s.density > 0.0 {
        (2.0 * s.dynamic_pressure / s.density).sqrt()
    } else {
        s.spherical[3]
    };
    trigger.function(s.density, airspeed)
}

/// The deployment point between the truth samples `prev` (trigger `c_prev > 0`) and `s`
/// (`c ≤ 0`), and its miss to `target` on a sphere of `radius`.
pub(super) fn deployment(
    prev: &TruthSample,
    s: &TruthSample,
    c_prev: f64,
    c: f64,
    target: &Target,
    radius: f64,
) -> Delivery {
    let w = c_prev / (c_prev - c);
    let lerp = |i: usize| prev.spherical[i] + w * (s.spherical[i] - prev.spherical[i]);
    let (lat, lon, psi) = (lerp(2), lerp(1), lerp(5));
    let dist = central_angle(lat, lon, target.lat, target.lon);
    let b = bearing(lat, lon, target.lat, target.lon);
    Delivery {
        t_deploy_s: prev.t + w * (s.t - prev.t),
        lat_deg: lat.to_degrees(),
        lon_deg: lon.to_degrees(),
        altitude_m: lerp(0) - radius,
        miss_m: radius * dist,
        downrange_m: -radius * dist * (b - psi).cos(),
        crossrange_m: radius * (dist.sin() * (b - psi).sin()).asin(),
        max_bank_rate_deg_s: 0.0,
        nav_error: None,
    }
}

/// Fly Monte Carlo run `run` of a study with master seed `seed` on `scenario` (its `[guidance]`)
/// with filter `kind` in the loop (module documentation). The truth realisation is the trade's
/// for the same (seed, run) ([`EntryCoSim::for_run`](super::engine::EntryCoSim::for_run)). The result carries the largest bank rate
/// flown, for the caller to hold against the limits ([`within_rate_limit`]).
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

/// Truth steps per guidance cycle (an error unless the period is a positive multiple of the step).
pub fn guidance_every(period_s: f64, step_s: f64) -> Result<usize, GuidedRunError> {
    let ratio = period_s / step_s;
    let every = ratio.round() as usize;
    if every == 0 || (ratio - every as f64).abs() > 1e-9 {
        return Err(GuidedRunError::Period { period_s, step_s });
    }
    Ok(every)
}

/// Whether every bank rate of a delivery stayed within `limits` (relative tolerance 1e-9).
pub fn within_rate_limit(d: &Delivery, limits: &BankLimits) -> bool {
    d.max_bank_rate_deg_s <= limits.rate_max.to_degrees() * (1.0 + 1e-9)
}
