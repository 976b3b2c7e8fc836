//! Closed-loop guided flight of the truth, with **perfect navigation**: guidance is handed the
//! truth's own state each cycle. A reference for what guidance can do before navigation errors
//! enter (the "perfect navigation" mode); it lives in `sim` because it reads the truth,
//! which the guidance layer may not.
//!
//! The loop: every guidance period the truth state becomes a [`NavState`] (planet-relative
//! spherical state and the true drag acceleration, what a perfect navigator and IMU would give),
//! guidance returns a bank command, and the bank actuator ([`BankActuator`]: rate and acceleration
//! limits) moves the flown bank towards it at every truth step. The truth advances with the
//! engine's own [`TruthPropagator`] (fixed-step RK4) until the deployment trigger, evaluated on
//! the truth (true density and airspeed); the deployment point is interpolated linearly in the
//! trigger function between the two truth steps around the crossing.
//!
//! The simulation engine does not call this yet (engine integration is future work); trades still
//! fly `truth.bank_deg`.

use crate::atmosphere::Atmosphere;
use crate::dynamics::EntryModel;
use crate::dynamics::aero::drag_lift;
use crate::frames::inertial_to_spherical;
use crate::guidance::{
    BankActuator, DeployBox, Guidance, GuidanceError, NavState, Target, Trigger,
    along_track_range_to_go, bearing, central_angle,
};
use crate::sim::engine::{SimError, TruthPropagator};
use nalgebra::SVector;
use thiserror::Error;

/// Why a guided flight failed.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum GuidedFlightError {
    /// The truth integration failed.
    #[error(transparent)]
    Truth(#[from] SimError),
    /// Guidance failed.
    #[error(transparent)]
    Guidance(#[from] GuidanceError),
    /// The truth never met the deployment trigger.
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
    /// The guidance period is not a positive multiple of the truth step.
    #[error("guidance period {period_s} s is not a positive multiple of the truth step {step_s} s")]
    Period {
        /// Guidance period \[s\].
        period_s: f64,
        /// Truth step \[s\].
        step_s: f64,
    },
}

/// Steps and limits of a guided flight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GuidedFlightSettings {
    /// Truth RK4 step \[s\].
    pub truth_step_s: f64,
    /// Guidance period \[s\] (a multiple of the truth step).
    pub guidance_period_s: f64,
    /// Longest flight \[s\].
    pub max_time_s: f64,
    /// Deployment trigger, on the truth (the truth is the onboard view here).
    pub trigger: Trigger,
    /// The deployment box: the range trigger's window.
    pub deploy_box: DeployBox,
}

/// One truth step of a guided flight.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GuidedSample {
    /// Time \[s\].
    pub t: f64,
    /// Bank flown over the step that ended here \[rad\].
    pub bank: f64,
    /// Bank command in force \[rad\].
    pub command: f64,
    /// Planet-relative spherical truth state `[r, lon, lat, v, fpa, heading]`.
    pub spherical: [f64; 6],
    /// True dynamic pressure \[Pa\].
    pub dynamic_pressure: f64,
}

/// The outcome of a guided flight.
#[derive(Debug, Clone, PartialEq)]
pub struct GuidedFlight {
    /// Every truth step (the start at index 0, with the initial bank).
    pub samples: Vec<GuidedSample>,
    /// Deployment time \[s\].
    pub t_deploy: f64,
    /// Deployment latitude and longitude \[rad\].
    pub deploy_lat_lon: [f64; 2],
    /// Deployment altitude \[m\].
    pub deploy_altitude_m: f64,
    /// Planet-relative speed at deployment \[m/s\].
    pub deploy_speed_mps: f64,
    /// Dynamic pressure at deployment \[Pa\].
    pub deploy_dynamic_pressure_pa: f64,
    /// Surface distance from the deployment point to the target \[m\].
    pub miss_m: f64,
    /// Along-track part of the miss, positive when the vehicle overflew the target \[m\].
    pub downrange_error_m: f64,
    /// Cross-track part of the miss, positive when the target lies to the right \[m\].
    pub crossrange_error_m: f64,
}

/// The truth's planet-relative spherical state and its true drag acceleration.
fn spherical_and_drag<A: Atmosphere>(
    truth: &EntryModel<A>,
    x: &SVector<f64, 6>,
    t: f64,
    density: f64,
    airspeed: f64,
    pos: &[f64; 3],
    vel: &[f64; 3],
) -> ([f64; 6], f64) {
    let s = if truth.kind.is_cartesian() {
        inertial_to_spherical(pos, vel, t, truth.planet.rotation_rate)
    } else {
        [x[0], x[1], x[2], x[3], x[4], x[5]]
    };
    let (d, _) = drag_lift(density, airspeed, &truth.aero_params(x, 0.0));
    (s, d)
}

/// Fly the truth `truth` from `x0` with `guidance` fed the truth (perfect navigation) and the
/// bank through `actuator`, to the deployment trigger; the miss is measured to `target`.
pub fn fly_perfect_navigation<A: Atmosphere>(
    truth: &EntryModel<A>,
    x0: SVector<f64, 6>,
    guidance: &mut dyn Guidance,
    mut actuator: BankActuator,
    target: &Target,
    settings: &GuidedFlightSettings,
) -> Result<GuidedFlight, GuidedFlightError> {
    let dt = settings.truth_step_s;
    let ratio = settings.guidance_period_s / dt;
    let every = ratio.round() as usize;
    if every == 0 || (ratio - every as f64).abs() > 1e-9 {
        return Err(GuidedFlightError::Period {
            period_s: settings.guidance_period_s,
            step_s: dt,
        });
    }
    let max_steps = (settings.max_time_s / dt).ceil() as usize;
    let mut prop = TruthPropagator::new(x0, dt, max_steps, None);
    let kin0 = crate::sensors::channels::kinematics(truth, &x0, 0.0);
    let (s0, d0) = spherical_and_drag(
        truth,
        &x0,
        0.0,
        kin0.density,
        kin0.airspeed,
        &kin0.pos,
        &kin0.vel,
    );
    let mut samples = vec![GuidedSample {
        t: 0.0,
        bank: actuator.bank,
        command: actuator.bank,
        spherical: s0,
        dynamic_pressure: 0.5 * kin0.density * kin0.airspeed * kin0.airspeed,
    }];
    let radius = truth.planet.radius;
    let trigger_fn = |s: &[f64; 6], density: f64, airspeed: f64| {
        truth_trigger(settings, target, radius, s, density, airspeed)
    };
    let mut nav = NavState {
        t: 0.0,
        spherical: s0,
        drag_mps2: d0,
    };
    let mut c_prev = trigger_fn(&s0, kin0.density, kin0.airspeed);
    let mut armed = c_prev > 0.0;
    let mut command = actuator.bank;
    for k in 0.. {
        if k % every == 0 {
            command = guidance.command(&nav)?;
        }
        let bank = actuator.step(command, dt);
        let Some(step) = prop.step(truth, bank)? else {
            break;
        };
        let (s, d) = spherical_and_drag(
            truth,
            &step.x,
            step.t,
            step.kin.density,
            step.kin.airspeed,
            &step.kin.pos,
            &step.kin.vel,
        );
        let (rho, va) = (step.kin.density, step.kin.airspeed);
        samples.push(GuidedSample {
            t: step.t,
            bank,
            command,
            spherical: s,
            dynamic_pressure: 0.5 * rho * va * va,
        });
        let c = trigger_fn(&s, rho, va);
        if armed && c <= 0.0 {
            return Ok(deployed(samples, (c_prev, c), step.t, dt, target, radius));
        }
        armed |= c > 0.0;
        c_prev = c;
        nav = NavState {
            t: step.t,
            spherical: s,
            drag_mps2: d,
        };
        if step.stop.is_some() {
            break;
        }
    }
    let last = samples.last().map(|s| s.spherical).unwrap_or(s0);
    Err(GuidedFlightError::NoTrigger {
        t_s: samples.last().map_or(0.0, |s| s.t),
        altitude_m: last[0] - truth.planet.radius,
        speed_mps: last[3],
    })
}

/// The trigger function of a flight whose onboard view is the truth: the scenario trigger on the
/// true density and airspeed, or the range trigger on the true position, speed and dynamic
/// pressure.
fn truth_trigger(
    settings: &GuidedFlightSettings,
    target: &Target,
    radius: f64,
    s: &[f64; 6],
    density: f64,
    airspeed: f64,
) -> f64 {
    match settings.trigger {
        Trigger::Range(rt) => {
            let nav = NavState {
                t: 0.0,
                spherical: *s,
                drag_mps2: 0.0,
            };
            let range = along_track_range_to_go(&nav, target, radius);
            let q = 0.5 * density * airspeed * airspeed;
            rt.function(&settings.deploy_box, range, airspeed, q)
        }
        t => t.function(density, airspeed),
    }
}

/// The flight that deployed on its last truth step (from `t − dt` to `t`), where the trigger
/// function went from `c_prev > 0` to `c ≤ 0`: the deployment point interpolated linearly in the
/// trigger function between the last two samples, and its miss to `target` on a sphere of
/// `radius`.
fn deployed(
    samples: Vec<GuidedSample>,
    (c_prev, c): (f64, f64),
    t: f64,
    dt: f64,
    target: &Target,
    radius: f64,
) -> GuidedFlight {
    let (p0, p1) = (samples[samples.len() - 2], samples[samples.len() - 1]);
    let (prev, s) = (p0.spherical, p1.spherical);
    let w = c_prev / (c_prev - c);
    let lerp = |i: usize| prev[i] + w * (s[i] - prev[i]);
    let (lat, lon, psi) = (lerp(2), lerp(1), lerp(5));
    let dist = central_angle(lat, lon, target.lat, target.lon);
    let b = bearing(lat, lon, target.lat, target.lon);
    GuidedFlight {
        t_deploy: t - dt + w * dt,
        deploy_lat_lon: [lat, lon],
        deploy_altitude_m: lerp(0) - radius,
        deploy_speed_mps: lerp(3),
        deploy_dynamic_pressure_pa: p0.dynamic_pressure
            + w * (p1.dynamic_pressure - p0.dynamic_pressure),
        miss_m: radius * dist,
        downrange_error_m: -radius * dist * (b - psi).cos(),
        crossrange_error_m: radius * (dist.sin() * (b - psi).sin()).asin(),
        samples,
    }
}
