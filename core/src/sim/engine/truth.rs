//! The truth side of the engine's step: one RK4 integration step of the truth with its stop rules
//! ([`TruthPropagator`]), the truth sample recorded at an instant ([`truth_sample`]) and the noisy
//! measurement epoch the sensors produce from it ([`measure_epoch`]).

use crate::atmosphere::Atmosphere;
use crate::dynamics::EntryModel;
use crate::dynamics::aero::drag_lift;
use crate::frames::inertial_to_spherical;
use crate::math::all_finite;
use crate::scenario::{Scenario, TruthDraw};
use crate::sensors::channels::{Kinematics, kinematics};
use crate::sensors::faults::{fault_error, is_stuck};
use crate::sensors::{MeasurementEpoch, dynamic_pressure, sutton_graves_heating};
use nalgebra::SVector;
use rand::Rng;
use rand_distr::{Distribution, StandardNormal};
use thiserror::Error;

/// Why a truth simulation failed.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SimError {
    /// The state became NaN or infinite.
    #[error(
        "truth state became non-finite at t = {t_s} s (state {state:?}); one step earlier the \
         vehicle was at altitude {altitude_m:.1} m in a density of {density_kgm3:e} kg/m³: check \
         the truth atmosphere (its table file and rows there) and the vehicle (truth.vehicle)"
    )]
    NonFinite {
        /// Time of failure \[s\].
        t_s: f64,
        /// Offending state.
        state: [f64; 6],
        /// Altitude of the last finite state \[m\].
        altitude_m: f64,
        /// The truth atmosphere's density there \[kg/m³\] (the usual culprit).
        density_kgm3: f64,
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

impl TruthSample {
    /// The density the *mean* atmosphere of `scenario` gives at this sample's altitude.
    pub fn mean_density(&self, scenario: &Scenario) -> f64 {
        scenario.truth_model.atmosphere.density(self.altitude)
    }
}

/// The truth sample of state `x` of the realisation `draw` at `t`, flown at bank `bank`.
pub fn truth_sample(
    scenario: &Scenario,
    draw: &TruthDraw,
    t: f64,
    x: &SVector<f64, 6>,
    bank: f64,
) -> TruthSample {
    let model = &draw.model;
    let kin = kinematics(model, x, t);
    let spherical = if model.kind.is_cartesian() {
        inertial_to_spherical(&kin.pos, &kin.vel, t, model.planet.rotation_rate)
    } else {
        [x[0], x[1], x[2], x[3], x[4], x[5]]
    };
    let p = model.aero_params(x, bank);
    let (d, l) = drag_lift(kin.density, kin.airspeed, &p);
    let h = scenario.measurement.heating;
    TruthSample {
        t,
        state: [x[0], x[1], x[2], x[3], x[4], x[5]],
        spherical,
        altitude: spherical[0] - model.planet.radius,
        density: kin.density,
        dynamic_pressure: dynamic_pressure(kin.density, kin.airspeed),
        heating: sutton_graves_heating(kin.density, kin.airspeed, h.k, h.nose_radius),
        aero_accel: (d * d + l * l).sqrt(),
        visible: scenario
            .beacons
            .iter()
            .zip(scenario.beacon_states(t).iter())
            .map(|(b, (p, _))| b.visibility_margin_from(p, kin.pos, model.planet.radius) > 0.0)
            .collect(),
    }
}

/// One truth integration step: step index, time, state and its kinematics, and whether the
/// truth stopped there.
#[derive(Debug, Clone, Copy)]
pub struct TruthStep {
    /// Step index k (time k·h).
    pub k: usize,
    /// Time \[s\].
    pub t: f64,
    /// State after the step.
    pub x: SVector<f64, 6>,
    /// Kinematics of `x` (inertial position and velocity, airspeed, density).
    pub kin: Kinematics<f64>,
    /// Set when this step ends the truth.
    pub stop: Option<StopReason>,
}

/// The truth integration: fixed-step RK4 (seed 000 §4: 1 s; [`EntryModel::step`]) with the stop
/// rules of a scenario's timing. The one place where a truth state advances in time: the engine,
/// the analysis points of the observability study and the training trajectories of seed 001's
/// Algorithm 1 all step it.
///
/// Stop rules, checked after every step, in this order: altitude ≤ 0 (ground), airspeed below
/// `stop_speed_mps` (parachute deployment), the last step `max_steps` (duration).
#[derive(Debug, Clone, PartialEq)]
pub struct TruthPropagator {
    x: SVector<f64, 6>,
    dt: f64,
    k: usize,
    max_steps: usize,
    stop_speed_mps: Option<f64>,
    stop: Option<StopReason>,
}

impl TruthPropagator {
    /// From `initial` with step `dt` \[s\] for at most `max_steps` steps, stopping below
    /// `stop_speed_mps` if given.
    pub fn new(
        initial: SVector<f64, 6>,
        dt: f64,
        max_steps: usize,
        stop_speed_mps: Option<f64>,
    ) -> Self {
        TruthPropagator {
            x: initial,
            dt,
            k: 0,
            max_steps,
            stop_speed_mps,
            stop: None,
        }
    }

    /// From `initial` with `scenario`'s timing (`truth_step_s`, `duration_s`, `stop_speed_mps`).
    pub fn for_scenario(scenario: &Scenario, initial: SVector<f64, 6>) -> Self {
        let timing = &scenario.config.timing;
        let dt = timing.truth_step_s;
        let max_steps = (timing.duration_s / dt).round().max(1.0) as usize;
        Self::new(initial, dt, max_steps, timing.stop_speed_mps)
    }

    /// Current state.
    pub fn state(&self) -> &SVector<f64, 6> {
        &self.x
    }

    /// Steps taken.
    pub fn steps(&self) -> usize {
        self.k
    }

    /// Integration step \[s\].
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// The last step index (the duration).
    pub fn max_steps(&self) -> usize {
        self.max_steps
    }

    /// Why the truth stopped, once it has.
    pub fn stop(&self) -> Option<StopReason> {
        self.stop
    }

    /// Advance one step along `steps`, a trajectory this propagator's start and stop rules
    /// produced before under the same model and bank (`steps[k]` is step k + 1): the same state,
    /// index and stop as [`TruthPropagator::step`] would give, without integrating. `None` once
    /// stopped or past the end of `steps`.
    pub fn follow(&mut self, steps: &[TruthStep]) -> Option<TruthStep> {
        if self.stop.is_some() {
            return None;
        }
        let s = *steps.get(self.k)?;
        debug_assert_eq!(s.k, self.k + 1, "a replayed step out of order");
        (self.x, self.k, self.stop) = (s.x, s.k, s.stop);
        Some(s)
    }

    /// Advance one step under `model` at bank `bank` \[rad\]; `Ok(None)` once stopped, an error
    /// (and no change) if the new state is not finite.
    pub fn step<A: Atmosphere>(
        &mut self,
        model: &EntryModel<A>,
        bank: f64,
    ) -> Result<Option<TruthStep>, SimError> {
        if self.stop.is_some() {
            return Ok(None);
        }
        let k = self.k + 1;
        let x = model.step(&self.x, bank, self.dt);
        let t = k as f64 * self.dt;
        if !all_finite(x.as_slice()) {
            return Err(SimError::NonFinite {
                t_s: t,
                state: [x[0], x[1], x[2], x[3], x[4], x[5]],
                altitude_m: model.altitude(&self.x),
                density_kgm3: model.density(&self.x),
            });
        }
        self.x = x;
        self.k = k;
        let kin = kinematics(model, &x, t);
        let r =
            (kin.pos[0] * kin.pos[0] + kin.pos[1] * kin.pos[1] + kin.pos[2] * kin.pos[2]).sqrt();
        self.stop = if r - model.planet.radius <= 0.0 {
            Some(StopReason::Ground)
        } else if self.stop_speed_mps.is_some_and(|v| kin.airspeed < v) {
            Some(StopReason::StopSpeed)
        } else if k == self.max_steps {
            Some(StopReason::Duration)
        } else {
            None
        };
        Ok(Some(TruthStep {
            k,
            t,
            x,
            kin,
            stop: self.stop,
        }))
    }
}

/// The measurement epoch at time `t` of the truth state `x` (kinematics `kin`, bank `bank`).
///
/// For every channel that is `due`, a noise value is drawn from `rng` in channel order *whether or
/// not the sample is available*, so an outage or a visibility change never shifts the noise of
/// other channels. A radio sample is available when its beacon is `commanded` (the FMU's
/// availability inputs), is not in a configured outage and, unless the scenario ignores
/// visibility, is `visible` above the horizon. A value is truth + bias + σ·z, with the sensor's
/// true σ (absolute, or relative to the true reading), plus the scenario's faults; a stuck
/// channel repeats the value it first took after its fault started (`held`, per channel).
pub(crate) fn measure_epoch<A: Atmosphere, const N: usize>(
    scenario: &Scenario,
    truth: &TruthAtEpoch<'_, A, N>,
    schedule: &EpochSchedule<'_, impl Fn(usize) -> bool, impl Fn(usize) -> bool>,
    rng: &mut impl Rng,
    held: &mut [Option<f64>],
) -> MeasurementEpoch {
    let t = truth.t;
    let beacon_states = scenario.beacon_states(t);
    let mut values = Vec::with_capacity(scenario.channels.len());
    let mut triad = None;
    for (c, spec) in scenario.channels.iter().enumerate() {
        if !(schedule.due)(c) {
            values.push(None);
            continue;
        }
        let reading = scenario.measurement.evaluate_sharing_triad(
            truth.model,
            truth.x,
            truth.kin,
            truth.bank,
            &beacon_states,
            spec.channel,
            &mut triad,
        );
        let z: f64 = StandardNormal.sample(rng);
        let available = match spec.channel.beacon() {
            Some(i) => {
                (schedule.commanded)(i)
                    && !scenario.config.beacons[i].in_outage(t)
                    && (scenario.config.ignore_visibility || schedule.visible[i])
            }
            None => true,
        };
        let fault = if scenario.faults.is_empty() {
            0.0
        } else {
            fault_error(&scenario.faults, spec.channel, t, rng)
        };
        let mut value = reading + spec.bias + spec.noise.sigma(reading) * z + fault;
        if !scenario.faults.is_empty()
            && is_stuck(&scenario.faults, spec.channel, t)
            && let Some(h) = held.get_mut(c)
        {
            value = *h.get_or_insert(value);
        }
        values.push(available.then_some(value));
    }
    MeasurementEpoch { t, values }
}

/// The truth at a measurement epoch: what the sensors measure.
pub(crate) struct TruthAtEpoch<'a, A, const N: usize> {
    /// The run's truth model.
    pub model: &'a EntryModel<A>,
    /// Truth state.
    pub x: &'a SVector<f64, N>,
    /// Its kinematics (accelerations, dynamic pressure).
    pub kin: &'a Kinematics<f64>,
    /// Epoch time \[s\].
    pub t: f64,
    /// Bank angle flown \[rad\].
    pub bank: f64,
}

/// Which channels are due at an epoch and which beacons can be heard.
pub(crate) struct EpochSchedule<'a, D, C> {
    /// Whether channel `c` is due.
    pub due: D,
    /// Per beacon, whether it is above the horizon.
    pub visible: &'a [bool],
    /// Per beacon, whether it is commanded available.
    pub commanded: C,
}
