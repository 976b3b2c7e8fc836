//! [`GuidedLoop`]: one dispersed entry with a navigation filter in the guidance loop, advanced one
//! truth step at a time (issue 28). [`super::guided_run::fly_with_filter`] is a loop over
//! [`GuidedLoop::step`], and the combined guided FMU (`MarsEntryNavGuided`) steps the same struct,
//! so the in-process flight and the FMU are the same code.
//!
//! Step k (truth grid, Δt = `timing.truth_step_s`):
//!
//! 1. if k is a multiple of the guidance period (a guidance cycle): the filter's latest estimate
//!    becomes the guidance layer's [`NavState`] ([`NavState::from_estimate`], with the sensed
//!    drag of the last accelerometer triad) and guidance gives a new command; a failed filter ends
//!    the run ([`GuidedRunError::FilterFailed`]);
//! 2. the [`BankActuator`] moves toward the command over Δt (rate and acceleration limits);
//! 3. the engine ([`EntryCoSim::do_step`]) advances the truth, the sensors and the filter by Δt
//!    with that bank;
//! 4. the accelerometer triad of the step's last epoch updates the sensed drag
//!    ([`crate::sensors::imu::ImuFrame::drag_from`]); the deployment trigger is evaluated on the
//!    truth and, once it has been positive and reaches 0, the run ends with its [`Delivery`]
//!    (interpolated between the two truth samples around the crossing). A truth that stops first
//!    ends the run with [`GuidedRunError::NoTrigger`].

use super::deployment::{Delivery, DeployNavError, deployment, trigger_on};
use super::guided_run_error::GuidedRunError;
use super::loop_inputs::{accel_slots, guidance_every, triad};
use crate::estimation::Onboard;
use crate::estimation::nav::FilterKind;
use crate::guidance::{BankActuator, BuiltGuidance, DeployBox, NavState, OnboardDeploy, Trigger};
use crate::scenario::Scenario;
use crate::sim::engine::{EntryCoSim, NavStatus, TruthSample};
use std::sync::Arc;

/// What guidance was given and what it flew on one truth step of a [`GuidedLoop`]: the onboard
/// inputs (what a guidance FMU connected to the navigation and truth FMUs receives) and the bank
/// flown. Never the truth.
#[derive(Debug, Clone, PartialEq)]
pub struct GuidedStep {
    /// Start of the truth step \[s\].
    pub t: f64,
    /// The filter's latest estimate (filter coordinates, every state) at the start of the step.
    pub est_x: Vec<f64>,
    /// Its 1σ.
    pub est_sigma: Vec<f64>,
    /// Its epoch \[s\].
    pub est_t: f64,
    /// The filter's status code ([`NavStatus::code`]).
    pub nav_status: i32,
    /// The accelerometer triad of the last measurement epoch of the previous step, in the IMU
    /// frame (`None`: no epoch with all three in that step, or the first step).
    pub accel: Option<[f64; 3]>,
    /// Whether a guidance cycle ran at the start of this step.
    pub cycle: bool,
    /// The command of the latest guidance cycle \[rad\].
    pub command: f64,
    /// The bank flown over the step, after the [`BankActuator`] \[rad\].
    pub bank: f64,
}

/// One guided flight with a filter in the loop, stepped on the truth grid (module documentation).
pub struct GuidedLoop {
    cosim: EntryCoSim,
    built: BuiltGuidance,
    trigger: Trigger,
    deploy_box: DeployBox,
    slots: [usize; 3],
    onboard: Arc<Onboard>,
    dt: f64,
    every: usize,
    radius: f64,
    actuator: BankActuator,
    /// Sensed drag of the last triad \[m/s²\] (0 before the first epoch: both algorithms fly their
    /// reference bank until the drag builds up).
    drag: f64,
    accel: Option<[f64; 3]>,
    command: f64,
    /// The bank flown over the last step (`None` before the first).
    flown: Option<f64>,
    max_rate: f64,
    prev: TruthSample,
    c_prev: f64,
    armed: bool,
    steps: usize,
    cycles: usize,
    end: Option<Result<Delivery, GuidedRunError>>,
}

impl std::fmt::Debug for GuidedLoop {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("GuidedLoop")
            .field("guidance", &self.built.guidance.name())
            .field("time", &self.cosim.time())
            .field("steps", &self.steps)
            .field("bank", &self.actuator.bank)
            .field("end", &self.end)
            .finish()
    }
}

impl GuidedLoop {
    /// Monte Carlo run `run` of a study with master seed `seed` on `scenario` (its `[guidance]`)
    /// with filter `kind` in the loop: the truth realisation is the trade's for the same (seed,
    /// run) ([`EntryCoSim::for_run`]), the actuator at rest at the reference bank.
    pub fn new(
        scenario: &Arc<Scenario>,
        kind: FilterKind,
        seed: u64,
        run: usize,
    ) -> Result<GuidedLoop, GuidedRunError> {
        let cosim = EntryCoSim::for_run(Arc::clone(scenario), kind, seed, run)?;
        GuidedLoop::with_cosim(scenario, cosim)
    }

    /// The guided flight of `cosim` (truth, sensors and filter at their start, built from
    /// `scenario`), the actuator at rest at the reference bank: what [`GuidedLoop::new`] flies
    /// for a study's run, and the combined guided FMU for its seed (dispersed or nominal).
    pub fn with_cosim(
        scenario: &Arc<Scenario>,
        cosim: EntryCoSim,
    ) -> Result<GuidedLoop, GuidedRunError> {
        let name = || scenario.config.name.clone();
        let cfg = scenario
            .config
            .guidance
            .as_ref()
            .ok_or_else(|| GuidedRunError::NoGuidance(name()))?;
        let slots = accel_slots(&scenario.onboard)
            .ok_or_else(|| GuidedRunError::NoAccelerometers(name()))?;
        let built = scenario
            .build_guidance()
            .ok_or_else(|| GuidedRunError::NoGuidance(name()))??;
        let dt = scenario.config.timing.truth_step_s;
        let every = guidance_every(cfg.period_s(), dt)?;
        let onboard = Arc::clone(cosim.nav().onboard());
        let actuator = BankActuator::new(built.limits, cfg.reference_bank_deg.to_radians());
        let radius = cosim.truth().draw().model.planet.radius;
        let prev = cosim.truth().outputs().sample.clone();
        let c_prev = trigger_on(&cfg.trigger, &prev);
        Ok(GuidedLoop {
            command: actuator.bank,
            actuator,
            trigger: cfg.trigger,
            deploy_box: cfg.deploy_box,
            built,
            slots,
            onboard,
            dt,
            every,
            radius,
            drag: 0.0,
            accel: None,
            flown: None,
            max_rate: 0.0,
            armed: c_prev > 0.0,
            prev,
            c_prev,
            steps: 0,
            cycles: 0,
            end: None,
            cosim,
        })
    }

    /// Record `e` as the end of the run and return it.
    fn fail(&mut self, e: GuidedRunError) -> GuidedRunError {
        self.end = Some(Err(e.clone()));
        e
    }

    /// One truth step (module documentation), with beacon availability `beacon_available` (missing
    /// entries count as available, as in [`EntryCoSim::do_step`]). Returns what guidance was given
    /// and flew; an error when the step could not fly (a failed filter or guidance at a cycle, or
    /// a step after the end). A step that flew may end the run — deployment, a truth that stopped
    /// before the trigger, an engine failure — which [`GuidedLoop::outcome`] then holds.
    pub fn step(&mut self, beacon_available: &[bool]) -> Result<GuidedStep, GuidedRunError> {
        if let Some(end) = &self.end {
            return Err(GuidedRunError::Ended(match end {
                Ok(d) => format!("deployed at t = {} s", d.t_deploy_s),
                Err(e) => e.to_string(),
            }));
        }
        let k = self.steps;
        let cycle = k % self.every == 0;
        let est = self.cosim.nav().estimate();
        let mut step = GuidedStep {
            t: self.cosim.time(),
            est_x: est.x.clone(),
            est_sigma: est.sigma.clone(),
            est_t: est.t,
            nav_status: self.cosim.nav().status().code(),
            accel: self.accel,
            cycle,
            command: self.command,
            bank: 0.0,
        };
        if cycle {
            if let NavStatus::Failed { t, reason } = self.cosim.nav().status() {
                let e = GuidedRunError::FilterFailed {
                    t_s: *t,
                    reason: reason.to_string(),
                };
                return Err(self.fail(e));
            }
            let model = &self.onboard.model;
            let nav = NavState::from_estimate(
                &est.x,
                model.kind.is_cartesian(),
                est.t,
                model.omega(),
                self.drag,
            );
            match nav.and_then(|nav| self.built.guidance.command(&nav)) {
                Ok(c) => self.command = c,
                Err(e) => return Err(self.fail(e.into())),
            }
            self.cycles += 1;
        }
        let before = self.actuator.bank;
        let bank = self.actuator.step(self.command, self.dt);
        step.command = self.command;
        step.bank = bank;
        self.max_rate = self.max_rate.max((bank - before).abs() / self.dt);
        self.flown = Some(bank);
        self.steps += 1;
        let t = self.cosim.time();
        let report = match self.cosim.do_step(t, self.dt, bank, beacon_available) {
            Ok(r) => r,
            Err(e) => {
                self.end = Some(Err(e.into()));
                return Ok(step);
            }
        };
        self.accel = self
            .cosim
            .truth()
            .last_epoch()
            .and_then(|e| triad(&self.slots, e));
        if let Some(a) = self.accel {
            self.drag = self.onboard.measurement.imu_frame.drag_from(&a);
        }
        let s = self.cosim.truth().outputs().sample.clone();
        let c = self.trigger_value(&s);
        if report.truth_steps > 0 && self.armed && c <= 0.0 {
            let mut d = deployment(
                (&self.prev, &s),
                (self.c_prev, c),
                &self.built.target,
                self.radius,
                &self.deploy_box,
            );
            d.max_bank_rate_deg_s = self.max_rate.to_degrees();
            let j = self.cosim.judgement();
            d.nav_error = Some(DeployNavError {
                position_m: j.pos_vel_err.0,
                velocity_mps: j.pos_vel_err.1,
                downrange_m: j.downrange_crossrange.0,
                crossrange_m: j.downrange_crossrange.1,
                nees_kinematic: j.nees_kinematic,
            });
            self.end = Some(Ok(d));
        } else if report.truth_steps == 0 || self.cosim.truth().stop().is_some() {
            self.end = Some(Err(GuidedRunError::NoTrigger {
                t_s: s.t,
                altitude_m: s.altitude,
                speed_mps: s.spherical[3],
            }));
        } else {
            self.armed |= c > 0.0;
            self.c_prev = c;
            self.prev = s;
        }
        Ok(step)
    }

    /// The trigger function after a step: the speed or dynamic-pressure trigger on the truth
    /// sample `s`, or the range trigger on the onboard view (the filter's latest estimate
    /// carried to the sample's time, the sensed drag over the filter's C_D S/m where it estimates
    /// one; [`crate::guidance::RangeTrigger::on_estimate`]).
    fn trigger_value(&self, s: &TruthSample) -> f64 {
        let Trigger::Range(rt) = self.trigger else {
            return trigger_on(&self.trigger, s);
        };
        let est = self.cosim.nav().estimate();
        let model = &self.onboard.model;
        let onboard = OnboardDeploy {
            target: self.built.target,
            radius: model.planet.radius,
            mu: model.planet.mu,
            cd_s_over_m: model.cd_s_over_m_of(est.x.as_slice()),
        };
        NavState::from_estimate(
            &est.x,
            model.kind.is_cartesian(),
            est.t,
            model.omega(),
            self.drag,
        )
        .map_or(self.c_prev, |nav| {
            rt.on_estimate(&self.deploy_box, &nav, s.t, &onboard)
        })
    }

    /// How the run ended (`None` while it flies): the delivery at deployment, or why it stopped.
    pub fn outcome(&self) -> Option<&Result<Delivery, GuidedRunError>> {
        self.end.as_ref()
    }

    /// The delivery, once deployed.
    pub fn delivery(&self) -> Option<&Delivery> {
        self.end.as_ref().and_then(|e| e.as_ref().ok())
    }

    /// The truth, sensors and filter.
    pub fn cosim(&self) -> &EntryCoSim {
        &self.cosim
    }

    /// Truth steps flown.
    pub fn steps(&self) -> usize {
        self.steps
    }

    /// Guidance cycles run.
    pub fn cycles(&self) -> usize {
        self.cycles
    }

    /// The truth step Δt \[s\].
    pub fn dt(&self) -> f64 {
        self.dt
    }

    /// The command of the latest guidance cycle (the reference bank before the first) \[rad\].
    pub fn command(&self) -> f64 {
        self.command
    }

    /// The actuator's bank: the bank flown over the last step (the reference bank before the
    /// first) \[rad\].
    pub fn bank(&self) -> f64 {
        self.actuator.bank
    }

    /// The actuator's bank rate \[rad/s\].
    pub fn bank_rate(&self) -> f64 {
        self.actuator.rate
    }

    /// The bank flown over the last step (`None` before the first) \[rad\].
    pub fn flown_bank(&self) -> Option<f64> {
        self.flown
    }

    /// The largest |bank change| / Δt over the steps flown \[rad/s\].
    pub fn max_bank_rate(&self) -> f64 {
        self.max_rate
    }

    /// The sensed drag guidance is given at the next cycle \[m/s²\].
    pub fn drag(&self) -> f64 {
        self.drag
    }
}
