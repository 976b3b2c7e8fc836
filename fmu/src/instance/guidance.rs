//! The engine of `MarsEntryGuidance`: the scenario's `[guidance]` fed with a navigation estimate
//! and the accelerometer triad, its command through the [`BankActuator`], stepped on the truth
//! step grid exactly as the in-process guided loop (`entrynav::sim::guided::guided_run`).
//!
//! **Time.** The actuator moves on the grid k·Δt of the scenario's `timing.truth_step_s`; a guidance
//! cycle runs at the start of every grid step k that is a multiple of the guidance period (P =
//! 1/`rate_hz`, a multiple of Δt). A communication step from t to t + h runs the grid steps that
//! end at or before t + h (as the truth FMU), so any step size works: a step shorter than Δt may
//! run none, a step longer than P runs several cycles, each with the inputs set before the step
//! (the first such step logs a warning). The outputs are the actuator's bank and rate after the
//! last grid step run. Nothing moves past the scenario's duration.
//!
//! **Inputs per cycle** (as `guided_run` gives them): [`NavState::from_estimate`] of `est_x_1..6`
//! at `nav_time` (spherical, or Cartesian converted with the onboard planet's rotation) and the
//! sensed drag, the onboard IMU frame's [`drag_from`](entrynav::sensors::imu::ImuFrame::drag_from)
//! of the last triad whose three `_valid` flags were set (0 before the first). The drag is
//! taken from the inputs at the start of each communication step.
//!
//! **Deployment** is judged on the navigation estimate (the vehicle has nothing else): the
//! trigger function with the estimated speed and the guidance model's density at the estimated
//! altitude (the range trigger: `RangeTrigger::on_estimate` from `nav_time` to the cycle's time,
//! the dynamic pressure read with the filter's C_D S/m from `est_x_7..` when the scenario's filter
//! estimates it, as the in-process loop decides it); once it has been positive and reaches 0, `deployed`
//! latches, cycles stop and the actuator settles on the last command. (The in-process loop
//! judges the speed and pressure triggers on the truth, which only it holds.)
//!
//! The engine keeps the onboard view only ([`Onboard`], the guidance model and the built
//! guidance): it never holds the truth.

use crate::vars::MAX_STATES;
use entrynav::atmosphere::AtmosphereModel;
use entrynav::dynamics::EntryModel;
use entrynav::estimation::Onboard;
use entrynav::guidance::longitudinal::LongModel;
use entrynav::guidance::{
    BankActuator, BuiltGuidance, DeployBox, NavState, OnboardDeploy, Trigger, onboard_trigger,
    range_crossrange,
};
use entrynav::scenario::Scenario;
use entrynav::sim::guided;
use std::sync::Arc;

pub use super::guidance_error::GuidanceStepError;

/// The inputs of one communication step.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct GuidanceInputs {
    /// `est_x_1..`[`MAX_STATES`]: the kinematic states, then the filter's augmented states
    /// (slots past its dimension read 0).
    pub est_x: [f64; MAX_STATES],
    /// `nav_time`.
    pub est_t: f64,
    /// `nav_status_code`.
    pub nav_status: i32,
    /// The triad `meas_accel_{x,y,z}` when all three `_valid` flags are set.
    pub accel: Option<[f64; 3]>,
}

/// What one communication step did.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct GuidanceReport {
    /// Grid steps run.
    pub steps: usize,
    /// Guidance cycles run.
    pub cycles: usize,
}

/// The guidance FMU's engine (module documentation).
pub struct GuidanceEngine {
    built: BuiltGuidance,
    model: EntryModel<AtmosphereModel>,
    onboard: Arc<Onboard>,
    trigger: Trigger,
    deploy: (DeployBox, OnboardDeploy),
    dt: f64,
    every: usize,
    max_steps: usize,
    steps: usize,
    time: f64,
    actuator: BankActuator,
    command: f64,
    drag: f64,
    cycles: u32,
    last_cycle_t: f64,
    range_to_go: f64,
    crossrange: f64,
    trigger_value: f64,
    armed: bool,
    deployed: bool,
}

impl std::fmt::Debug for GuidanceEngine {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GuidanceEngine")
            .field("guidance", &self.built.guidance.name())
            .field("time", &self.time)
            .field("steps", &self.steps)
            .field("bank", &self.actuator.bank)
            .field("deployed", &self.deployed)
            .finish()
    }
}

/// The largest speed an estimate may have \[m/s\] (entry speeds at Mars are below 8 km/s).
const MAX_SPEED_MPS: f64 = 20_000.0;

impl GuidanceEngine {
    /// From `scenario`'s `[guidance]` and onboard view (the truth is not kept).
    pub fn new(scenario: &Scenario) -> Result<GuidanceEngine, GuidanceStepError> {
        let name = || scenario.config.name.clone();
        let cfg = scenario
            .config
            .guidance
            .as_ref()
            .ok_or_else(|| GuidanceStepError::NoGuidance(name()))?;
        if guided::accel_slots(&scenario.onboard).is_none() {
            return Err(GuidanceStepError::NoAccelerometers(name()));
        }
        let built = scenario
            .build_guidance()
            .ok_or_else(|| GuidanceStepError::NoGuidance(name()))??;
        let model = scenario
            .guidance_model()
            .ok_or_else(|| GuidanceStepError::NoGuidance(name()))?;
        let timing = &scenario.config.timing;
        let dt = timing.truth_step_s;
        let every =
            guided::guidance_every(cfg.period_s(), dt).map_err(|_| GuidanceStepError::Period {
                period_s: cfg.period_s(),
                step_s: dt,
            })?;
        // Checked against the run bound by `limits::check_scenario` before this is called.
        let max_steps = (timing.duration_s / dt).round() as usize;
        let bank0 = cfg.reference_bank_deg.to_radians();
        let onboard_deploy = OnboardDeploy {
            target: built.target,
            radius: model.planet.radius,
            mu: model.planet.mu,
            cd_s_over_m: model.vehicle.cd_s_over_m,
        };
        Ok(GuidanceEngine {
            actuator: BankActuator::new(built.limits, bank0),
            built,
            model,
            onboard: Arc::clone(&scenario.onboard),
            trigger: cfg.trigger,
            deploy: (cfg.deploy_box, onboard_deploy),
            dt,
            every,
            max_steps,
            steps: 0,
            time: 0.0,
            command: bank0,
            drag: 0.0,
            cycles: 0,
            last_cycle_t: 0.0,
            range_to_go: 0.0,
            crossrange: 0.0,
            trigger_value: 0.0,
            armed: false,
            deployed: false,
        })
    }

    /// The current communication point.
    pub fn time(&self) -> f64 {
        self.time
    }

    /// The grid steps a communication step from `t` by `h` runs: from the current one up to
    /// the last that ends at or before `t + h`, never past the scenario's duration.
    fn end_step(&self, t: f64, h: f64) -> usize {
        let k = ((t + h) / self.dt + 1e-7).floor().max(0.0) as usize;
        k.min(self.max_steps).max(self.steps)
    }

    /// Guidance cycles a step up to grid step `end` runs.
    fn cycles_until(&self, end: usize) -> usize {
        if self.deployed || end <= self.steps {
            return 0;
        }
        let first = self.steps.div_ceil(self.every) * self.every;
        if first >= end {
            0
        } else {
            (end - 1 - first) / self.every + 1
        }
    }

    /// The navigation state of `inputs`, checked.
    fn nav_state(&self, inputs: &GuidanceInputs, drag: f64) -> Result<NavState, GuidanceStepError> {
        let bad = |what: String| GuidanceStepError::Estimate {
            t: inputs.est_t,
            what,
        };
        if inputs.nav_status == 2 {
            return Err(GuidanceStepError::NavFailed(inputs.est_t));
        }
        let m = &self.onboard.model;
        let nav = NavState::from_estimate(
            &inputs.est_x,
            m.kind.is_cartesian(),
            inputs.est_t,
            m.omega(),
            drag,
        )?;
        let radius = self.model.planet.radius;
        let [r, _, lat, v, fpa, _] = nav.spherical;
        if !(r > 0.5 * radius && r <= 2.0 * radius) {
            return Err(bad(format!(
                "radius {r} m is not between half and twice the planet radius ({radius} m)"
            )));
        }
        if !(v > 0.0 && v <= MAX_SPEED_MPS) {
            return Err(bad(format!(
                "speed {v} m/s is not in (0, {MAX_SPEED_MPS}] m/s"
            )));
        }
        let half_pi = std::f64::consts::FRAC_PI_2;
        if lat.abs() > half_pi || fpa.abs() > half_pi {
            return Err(bad(format!(
                "latitude {lat} rad or flight-path angle {fpa} rad is beyond ±π/2"
            )));
        }
        Ok(nav)
    }

    /// Refuse, before anything changes, a step whose cycles would fly inputs guidance cannot use
    /// (a failed filter, an estimate out of bounds); returns the cycles the step will run.
    pub fn check(
        &self,
        t: f64,
        h: f64,
        inputs: &GuidanceInputs,
    ) -> Result<usize, GuidanceStepError> {
        let cycles = self.cycles_until(self.end_step(t, h));
        if cycles > 0 {
            self.nav_state(inputs, 0.0)?;
        }
        Ok(cycles)
    }

    /// One communication step from `t` by `h` (module documentation). The caller checks the
    /// communication point and [`GuidanceEngine::check`]s the inputs first; an error here is a
    /// failure of the guidance law inside the step.
    pub fn do_step(
        &mut self,
        t: f64,
        h: f64,
        inputs: &GuidanceInputs,
    ) -> Result<GuidanceReport, GuidanceStepError> {
        // The triad the truth measured over its last step: what this step's cycles see, as in
        // the in-process loop (the drag read after each truth step, before the next cycle).
        if let Some(a) = inputs.accel {
            self.drag = self.onboard.measurement.imu_frame.drag_from(&a);
        }
        let end = self.end_step(t, h);
        let mut report = GuidanceReport::default();
        while self.steps < end {
            if !self.deployed && self.steps % self.every == 0 {
                self.cycle(inputs)?;
                report.cycles += 1;
            }
            self.actuator.step(self.command, self.dt);
            self.steps += 1;
            report.steps += 1;
        }
        self.time = t + h;
        Ok(report)
    }

    fn cycle(&mut self, inputs: &GuidanceInputs) -> Result<(), GuidanceStepError> {
        let nav = self.nav_state(inputs, self.drag)?;
        let lm = LongModel {
            model: &self.model,
            density_scale: 1.0,
            trigger: self.trigger,
        };
        let ((window, mut onboard), rho) = (self.deploy, lm.density(nav.spherical[0]));
        onboard.cd_s_over_m = self.onboard.model.cd_s_over_m_of(&inputs.est_x);
        let now = (self.steps as f64 * self.dt).max(nav.t); // the range trigger carries to now
        let c = onboard_trigger(&self.trigger, &window, &nav, now, rho, &onboard);
        let (d, xr) = range_crossrange(&nav, &self.built.target);
        let radius = self.model.planet.radius;
        self.trigger_value = c;
        self.range_to_go = d * radius;
        self.crossrange = xr * radius;
        self.last_cycle_t = self.steps as f64 * self.dt;
        self.cycles += 1;
        if self.armed && c <= 0.0 {
            self.deployed = true;
            return Ok(());
        }
        self.armed |= c > 0.0;
        let command = self.built.guidance.command(&nav)?;
        if !command.is_finite() {
            // The actuator would carry a NaN for the rest of the run while the output reads 0.
            return Err(GuidanceStepError::NonFiniteCommand(nav.t));
        }
        self.command = command;
        Ok(())
    }

    /// The bank to fly (the actuator's) \[rad\].
    pub fn bank(&self) -> f64 {
        self.actuator.bank
    }

    /// The actuator's bank rate \[rad/s\].
    pub fn bank_rate(&self) -> f64 {
        self.actuator.rate
    }

    /// The latest command \[rad\].
    pub fn command(&self) -> f64 {
        self.command
    }

    /// Time of the latest cycle \[s\].
    pub fn last_cycle_time(&self) -> f64 {
        self.last_cycle_t
    }

    /// Cycles run.
    pub fn cycles(&self) -> u32 {
        self.cycles
    }

    /// The sensed drag of the last valid triad \[m/s²\].
    pub fn drag(&self) -> f64 {
        self.drag
    }

    /// Range to go and crossrange at the latest cycle \[m\].
    pub fn range(&self) -> (f64, f64) {
        (self.range_to_go, self.crossrange)
    }

    /// The trigger function at the latest cycle.
    pub fn trigger_value(&self) -> f64 {
        self.trigger_value
    }

    /// Whether the trigger was reached on the estimate.
    pub fn deployed(&self) -> bool {
        self.deployed
    }

    /// The item of the Enumeration `GuidanceStatus` ([`crate::vars::GUIDANCE_STATUS`]):
    /// 0 waiting (no cycle yet), 1 flying, 2 deployed.
    pub fn status(&self) -> i32 {
        if self.deployed {
            2
        } else {
            i32::from(self.cycles > 0)
        }
    }
}
