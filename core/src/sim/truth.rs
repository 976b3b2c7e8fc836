//! Truth simulator: fixed-step RK4 truth trajectory and noisy measurement records.

use crate::atmosphere::Atmosphere;
use crate::dynamics::EntryModel;
use crate::frames::inertial_to_spherical;
use crate::scenario::{Scenario, TruthDraw};
use crate::sensors::channels::{Kinematics, kinematics};
use crate::sensors::{Channel, dynamic_pressure, sutton_graves_heating};
use nalgebra::SVector;
use rand::Rng;
use rand_distr::{Distribution, StandardNormal};
use thiserror::Error;

/// Why a truth simulation failed.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SimError {
    /// The state became NaN or infinite.
    #[error("truth state became non-finite at t = {t_s} s (state {state:?})")]
    NonFinite {
        /// Time of failure \[s\].
        t_s: f64,
        /// Offending state.
        state: [f64; 6],
    },
}

/// Why the truth simulation ended.
#[derive(Debug, Clone, Copy, PartialEq, Eq, serde::Serialize)]
#[serde(rename_all = "kebab-case")]
pub enum StopReason {
    /// Reached `timing.duration_s`.
    Duration,
    /// Speed fell below `timing.stop_speed_mps` (parachute deployment trigger).
    StopSpeed,
    /// Altitude reached zero.
    Ground,
}

/// The true vehicle state at one instant, with derived quantities.
#[derive(Debug, Clone, PartialEq)]
pub struct TruthSample {
    /// Time \[s\].
    pub t: f64,
    /// State in the truth model's coordinates.
    pub state: [f64; 6],
    /// Planet-relative spherical state `[r, lon, lat, v, fpa, heading]` (internal convention).
    pub spherical: [f64; 6],
    /// Altitude above the reference sphere \[m\].
    pub altitude: f64,
    /// True density [kg/m³].
    pub density: f64,
    /// Dynamic pressure \[Pa\].
    pub dynamic_pressure: f64,
    /// Sutton–Graves heating rate with the scenario's heating constants [W/m²].
    pub heating: f64,
    /// Magnitude of the aerodynamic (non-gravitational) acceleration [m/s²].
    pub aero_accel: f64,
    /// Beacon visibility (geometric; independent of outages and of `ignore_visibility`).
    pub visible: Vec<bool>,
}

/// Measurements taken at one instant: one slot per scenario channel.
#[derive(Debug, Clone, PartialEq)]
pub struct MeasurementEpoch {
    /// Time \[s\].
    pub t: f64,
    /// `Some(value)` when the channel was sampled and available; `None` when it was not due,
    /// its beacon was in an outage, or (unless visibility is ignored) below the horizon.
    pub values: Vec<Option<f64>>,
}

/// A complete truth run.
#[derive(Debug, Clone)]
pub struct TruthRun {
    /// Truth samples at t = 0, at every measurement epoch, and at the final time.
    pub samples: Vec<TruthSample>,
    /// Measurement epochs (aligned with `samples[1..]`).
    pub epochs: Vec<MeasurementEpoch>,
    /// Why it ended.
    pub stop: StopReason,
}

fn sample(scenario: &Scenario, draw: &TruthDraw, t: f64, x: &SVector<f64, 6>) -> TruthSample {
    let model = &draw.model;
    let kin = kinematics(model, x, t);
    let spherical = if model.kind.is_cartesian() {
        inertial_to_spherical(&kin.pos, &kin.vel, t, model.planet.rotation_rate)
    } else {
        [x[0], x[1], x[2], x[3], x[4], x[5]]
    };
    let altitude = spherical[0] - model.planet.radius;
    let p = model.aero_params(x, scenario.truth_bank);
    let (d, l) = crate::dynamics::aero::drag_lift(kin.density, kin.airspeed, &p);
    let h = scenario.measurement.heating;
    let visible = scenario
        .beacons
        .iter()
        .map(|b| b.visible_from(kin.pos, t, model.planet.radius))
        .collect();
    TruthSample {
        t,
        state: [x[0], x[1], x[2], x[3], x[4], x[5]],
        spherical,
        altitude,
        density: kin.density,
        dynamic_pressure: dynamic_pressure(kin.density, kin.airspeed),
        heating: sutton_graves_heating(kin.density, kin.airspeed, h.k, h.nose_radius),
        aero_accel: (d * d + l * l).sqrt(),
        visible,
    }
}

/// Simulate one truth run of `scenario` for the realisation `draw`, drawing measurement noise
/// from `rng`.
///
/// The truth is integrated with fixed-step RK4 at `timing.truth_step_s`. A channel with period P is
/// sampled at t = P, 2P, … (every sensor period is validated to be a multiple of the step). For
/// every scheduled sample a noise value is drawn *whether or not the measurement is available*, in
/// channel order, so an outage or a visibility change never shifts the noise of other channels.
pub fn simulate_truth(
    scenario: &Scenario,
    draw: &TruthDraw,
    rng: &mut impl Rng,
) -> Result<TruthRun, SimError> {
    let timing = &scenario.config.timing;
    let h = timing.truth_step_s;
    let n_steps = (timing.duration_s / h).round().max(1.0) as usize;
    let periods: Vec<usize> = scenario
        .channels
        .iter()
        .map(|c| (c.period_s / h).round().max(1.0) as usize)
        .collect();
    let model = &draw.model;
    let bank = scenario.truth_bank;
    let mut x = draw.initial;
    let mut samples = vec![sample(scenario, draw, 0.0, &x)];
    let mut epochs = Vec::new();
    let mut stop = StopReason::Duration;
    for k in 1..=n_steps {
        x = model.step(&x, bank, h);
        let t = k as f64 * h;
        if x.iter().any(|v| !v.is_finite()) {
            return Err(SimError::NonFinite {
                t_s: t,
                state: [x[0], x[1], x[2], x[3], x[4], x[5]],
            });
        }
        let due: Vec<bool> = periods.iter().map(|p| k % p == 0).collect();
        let is_last = k == n_steps;
        // Cheap per-step checks; the full sample (visibility of every beacon…) only when recorded.
        let kin = kinematics(model, &x, t);
        let (altitude, airspeed) = {
            let r = (kin.pos[0] * kin.pos[0] + kin.pos[1] * kin.pos[1] + kin.pos[2] * kin.pos[2])
                .sqrt();
            (r - model.planet.radius, kin.airspeed)
        };
        let ground = altitude <= 0.0;
        let slow = timing.stop_speed_mps.is_some_and(|v| airspeed < v);
        let any_due = due.iter().any(|d| *d);
        if !(any_due || is_last || ground || slow) {
            continue;
        }
        let s = sample(scenario, draw, t, &x);
        if any_due {
            epochs.push(measure_epoch(
                scenario,
                model,
                &x,
                &kin,
                t,
                bank,
                |c| due[c],
                &s.visible,
                |_| true,
                rng,
            ));
        }
        samples.push(s);
        if ground {
            stop = StopReason::Ground;
            break;
        }
        if slow {
            stop = StopReason::StopSpeed;
            break;
        }
    }
    Ok(TruthRun {
        samples,
        epochs,
        stop,
    })
}

/// The measurement epoch at time `t` of the truth state `x` (kinematics `kin`, bank `bank`).
///
/// For every channel that is `due`, a noise value is drawn from `rng` in channel order *whether or
/// not the sample is available*, so an outage or a visibility change never shifts the noise of
/// other channels. A radio sample is available when its beacon is `commanded` (the FMU's
/// availability inputs; always for [`simulate_truth`]), is not in a configured outage and, unless
/// the scenario ignores visibility, is `visible` above the horizon.
#[allow(clippy::too_many_arguments)]
pub(crate) fn measure_epoch<A: Atmosphere, const N: usize>(
    scenario: &Scenario,
    model: &EntryModel<A>,
    x: &SVector<f64, N>,
    kin: &Kinematics<f64>,
    t: f64,
    bank: f64,
    due: impl Fn(usize) -> bool,
    visible: &[bool],
    commanded: impl Fn(usize) -> bool,
    rng: &mut impl Rng,
) -> MeasurementEpoch {
    let beacon_states = scenario.beacon_states(t);
    let mut values = Vec::with_capacity(scenario.channels.len());
    for (c, spec) in scenario.channels.iter().enumerate() {
        if !due(c) {
            values.push(None);
            continue;
        }
        let truth =
            scenario
                .measurement
                .evaluate_with(model, x, kin, bank, &beacon_states, spec.channel);
        let z: f64 = StandardNormal.sample(rng);
        let available = match spec.channel.beacon() {
            Some(i) => {
                commanded(i)
                    && !scenario.config.beacons[i].in_outage(t)
                    && (scenario.config.ignore_visibility || visible[i])
            }
            None => true,
        };
        values.push(available.then(|| truth + spec.bias + spec.noise.sigma(truth) * z));
    }
    MeasurementEpoch { t, values }
}

/// Channel names of a scenario, in measurement-slot order.
pub fn channel_names(scenario: &Scenario) -> Vec<String> {
    scenario.channels.iter().map(|c| c.name.clone()).collect()
}

/// Whether a channel is a radio channel (its slots may be empty for outages and visibility).
pub fn is_radio(channel: Channel) -> bool {
    channel.beacon().is_some()
}

impl TruthSample {
    /// The density the *mean* atmosphere of `scenario` gives at this sample's altitude.
    pub fn mean_density(&self, scenario: &Scenario) -> f64 {
        scenario.truth_model.atmosphere.density(self.altitude)
    }
}
