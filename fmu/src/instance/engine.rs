//! The simulation behind an instance: which engine a model runs, the scenario it is built from
//! (see [`super::scenario`]), the work bounds of a step, and one communication step.

use super::guidance::{GuidanceEngine, GuidanceInputs, GuidanceStepError};
use super::guided::GuidedEngine;
use super::scenario::{ScenarioFileError, load_parameter_scenario};
use super::{Instance, Status};
use crate::limits::{self, LimitError, STEP_CHUNK_TRUTH_STEPS};
use crate::vars::{Key, MAX_BEACONS, Model, Slot, Value};
use entrynav::estimation::nav::{FilterKind, NavError};
use entrynav::scenario::Scenario;
use entrynav::sensors::{Channel, MeasurementEpoch};
use entrynav::sim::engine::{
    EngineError, EntryCoSim, NavStatus, Navigator, StepReport, TruthSensors,
};
use entrynav::sim::guided::GuidedRunError;
use std::sync::Arc;
use thiserror::Error;

/// Why an instance cannot build or step its engine, or refuses a value.
#[derive(Debug, Error)]
pub enum InstanceError {
    /// The scenario could not be loaded.
    #[error(transparent)]
    Scenario(#[from] ScenarioFileError),
    /// A request or a scenario over a bound of [`crate::limits`].
    #[error(transparent)]
    Limit(#[from] LimitError),
    /// The filter parameter names no filter, or the filter does not fit the scenario.
    #[error(transparent)]
    Filter(#[from] NavError),
    /// The engine refused a step or failed.
    #[error(transparent)]
    Engine(#[from] EngineError),
    /// A real value that is NaN or infinite.
    #[error("{0} is not a finite number")]
    NonFinite(f64),
    /// A negative seed.
    #[error("seed must be >= 0, got {0}")]
    NegativeSeed(i32),
    /// An empty scenario name.
    #[error("the scenario name is empty")]
    EmptyScenario,
    /// A string longer than the bound.
    #[error("{0}")]
    TooLong(LimitError),
    /// No engine where one must exist (an internal error).
    #[error("no engine")]
    NoEngine,
    /// The guidance FMU cannot be built, refuses its inputs or failed.
    #[error(transparent)]
    Guidance(#[from] GuidanceStepError),
    /// A negative 1σ input.
    #[error("a 1-sigma must be >= 0, got {0}")]
    NegativeSigma(f64),
    /// The guided FMU cannot be built or its loop failed.
    #[error(transparent)]
    Guided(#[from] GuidedRunError),
    /// A Monte Carlo run index out of range.
    #[error("run must be in 0..={max}, got {got}")]
    Run {
        /// The value given.
        got: i32,
        /// The largest allowed.
        max: i32,
    },
    /// A filter status code that is not 0, 1 or 2.
    #[error("{0} is not a filter status code (0 initial, 1 running, 2 failed)")]
    StatusCode(i32),
}

/// The simulation behind an instance.
#[derive(Debug)]
pub enum Engine {
    /// Truth, sensors and filter.
    Combined(Box<EntryCoSim>),
    /// Truth and sensors.
    Truth(Box<TruthSensors>),
    /// Filter alone: it sees only its onboard view ([`Navigator::onboard`]), and the instance
    /// keeps of the scenario only the run's duration, which bounds the filter's prediction.
    Filter {
        /// The filter.
        nav: Box<Navigator>,
        /// The scenario's `timing.duration_s`.
        duration_s: f64,
    },
    /// Guidance alone: the onboard view and `[guidance]` only.
    Guidance(Box<GuidanceEngine>),
    /// Truth, sensors, filter and guidance in one loop.
    Guided(Box<GuidedEngine>),
}

impl Engine {
    /// The measurement channels, in the order of an epoch's values.
    pub(super) fn channels(&self) -> Vec<Channel> {
        let of_scenario = |s: &Scenario| s.channels.iter().map(|c| c.channel).collect();
        match self {
            Engine::Combined(c) => of_scenario(c.truth().scenario()),
            Engine::Guided(g) => of_scenario(g.flight().cosim().truth().scenario()),
            Engine::Truth(t) => of_scenario(t.scenario()),
            Engine::Filter { nav, .. } => {
                nav.onboard().channels.iter().map(|c| c.channel).collect()
            }
            // Its accelerometer inputs are read by key, not through an epoch's channel list.
            Engine::Guidance(_) => Vec::new(),
        }
    }

    pub(super) fn truth(&self) -> Option<&TruthSensors> {
        match self {
            Engine::Combined(c) => Some(c.truth()),
            Engine::Guided(g) => Some(g.flight().cosim().truth()),
            Engine::Truth(t) => Some(t),
            Engine::Filter { .. } | Engine::Guidance(_) => None,
        }
    }

    pub(super) fn nav(&self) -> Option<&Navigator> {
        match self {
            Engine::Combined(c) => Some(c.nav()),
            Engine::Guided(g) => Some(g.flight().cosim().nav()),
            Engine::Filter { nav, .. } => Some(nav),
            Engine::Truth(_) | Engine::Guidance(_) => None,
        }
    }

    /// Truth, sensors and filter together (the combined and guided models), for the judgement.
    pub(super) fn cosim(&self) -> Option<&EntryCoSim> {
        match self {
            Engine::Combined(c) => Some(c),
            Engine::Guided(g) => Some(g.flight().cosim()),
            _ => None,
        }
    }

    /// Current communication point.
    pub fn time(&self) -> f64 {
        match self {
            Engine::Combined(c) => c.time(),
            Engine::Guided(g) => g.time(),
            Engine::Truth(t) => t.time(),
            Engine::Filter { nav, .. } => nav.time(),
            Engine::Guidance(g) => g.time(),
        }
    }
}

impl Instance {
    /// The scenario: the embedded one of a specific FMU, else the one the parameters name.
    fn load_scenario(&self) -> Result<Arc<Scenario>, InstanceError> {
        if let Some(s) = self.spec.specific() {
            return Ok(Arc::clone(&s.scenario));
        }
        let allow = self.input_bool(Key::AllowExternalFiles, false);
        Ok(load_parameter_scenario(
            &self.param_str(Key::Scenario),
            &self.resources,
            allow,
        )?)
    }

    fn build_engine(&self) -> Result<Engine, InstanceError> {
        let scenario = self.load_scenario()?;
        limits::check_scenario(&scenario)?;
        let seed = match self.value_of(Key::Seed) {
            Some(Value::Integer(s)) => *s as u64,
            _ => 0,
        };
        let dispersed = self.input_bool(Key::Dispersed, false);
        let kind = || FilterKind::parse(&self.param_str(Key::Filter));
        let n_beacons = scenario.beacons.len();
        if n_beacons > MAX_BEACONS {
            self.warn(&format!(
                "scenario has {n_beacons} beacons; only the first {MAX_BEACONS} have FMU variables"
            ));
        }
        Ok(match self.model {
            Model::Combined => Engine::Combined(Box::new(EntryCoSim::new(
                scenario,
                kind()?,
                seed,
                dispersed,
            )?)),
            Model::Filter => {
                let nav = Navigator::for_seed(&scenario, kind()?, seed, dispersed)?;
                Engine::Filter {
                    nav: Box::new(nav),
                    duration_s: scenario.config.timing.duration_s,
                }
            }
            Model::Truth => Engine::Truth(Box::new(TruthSensors::new(scenario, seed, dispersed))),
            Model::Guidance => Engine::Guidance(Box::new(GuidanceEngine::new(&scenario)?)),
            Model::Guided => {
                let cosim = if dispersed {
                    let run = match self.value_of(Key::Run) {
                        Some(Value::Integer(r)) => *r,
                        _ => 0,
                    };
                    check_run(run)?;
                    EntryCoSim::for_run(Arc::clone(&scenario), kind()?, seed, run as usize)?
                } else {
                    EntryCoSim::new(Arc::clone(&scenario), kind()?, seed, false)?
                };
                Engine::Guided(Box::new(GuidedEngine::new(&scenario, cosim)?))
            }
        })
    }

    pub(super) fn ensure_engine(&mut self) -> Result<(), InstanceError> {
        if self.engine.is_none() {
            let e = self.build_engine()?;
            self.slot_channel = e
                .channels()
                .into_iter()
                .enumerate()
                .filter_map(|(i, c)| Slot::of(c).map(|s| (s, i)))
                .collect();
            self.engine = Some(e);
        }
        Ok(())
    }

    /// The measurement epoch the filter FMU's inputs describe, if `meas_epoch` is set.
    fn input_epoch(&self) -> Option<MeasurementEpoch> {
        let Some(Engine::Filter { nav, .. }) = &self.engine else {
            return None;
        };
        if !self.input_bool(Key::MeasEpoch, false) {
            return None;
        }
        let n = nav.onboard().channels.len();
        let mut values = vec![None; n];
        for (slot, &c) in &self.slot_channel {
            if self.input_bool(Key::MeasValid(*slot), false) {
                values[c] = Some(self.input_real(Key::Meas(*slot)));
            }
        }
        Some(MeasurementEpoch {
            t: self.input_real(Key::MeasTime),
            values,
        })
    }

    /// Refuse, before anything changes, a step whose work is over a bound: the filter FMU's
    /// prediction to an input epoch it would process. (The truth's work is bounded by the
    /// scenario, checked when the engine is built.)
    pub(super) fn check_step_work(&self, t: f64, h: f64) -> Result<(), LimitError> {
        let (Some(Engine::Filter { nav, duration_s }), Some(epoch)) =
            (&self.engine, self.input_epoch())
        else {
            return Ok(());
        };
        let last = nav.estimate().t;
        let processed = !matches!(nav.status(), NavStatus::Failed { .. })
            && epoch.t > last
            && epoch.t <= t + h + 1e-9;
        if !processed {
            return Ok(());
        }
        limits::check_prediction(last, epoch.t, nav.onboard().filter_step_s, *duration_s)
    }

    /// One step of the combined engine, advanced in chunks of at most
    /// [`STEP_CHUNK_TRUTH_STEPS`] truth steps so the epochs of a long step are never collected
    /// all at once. Chunks end on truth-step boundaries; the last ends at `t + h`.
    fn step_combined(
        c: &mut EntryCoSim,
        t: f64,
        h: f64,
        bank: f64,
        avail: &[bool],
    ) -> Result<StepReport, EngineError> {
        let dt = c.truth().scenario().config.timing.truth_step_s;
        let chunk = STEP_CHUNK_TRUTH_STEPS as f64;
        let end = t + h;
        let mut report = StepReport::default();
        let mut from = t;
        // Once the truth has stopped a step does no work, so the rest is one call (at most
        // MAX_RUN_TRUTH_STEPS / STEP_CHUNK_TRUTH_STEPS chunks come before that).
        while (end - from) / dt > chunk + 1.0 && c.truth().stop().is_none() {
            let to = ((from / dt).floor() + chunk) * dt;
            let r = c.do_step(from, to - from, bank, avail)?;
            report.truth_steps += r.truth_steps;
            report.epochs += r.epochs;
            from = to;
        }
        // An unchunked step is passed as asked (a step too small to move t still counts).
        let last = if from == t { h } else { end - from };
        let r = c.do_step(from, last, bank, avail)?;
        report.truth_steps += r.truth_steps;
        report.epochs += r.epochs;
        Ok(report)
    }

    pub(super) fn step_engine(&mut self, t: f64, h: f64) -> Result<Status, InstanceError> {
        let bank = self.input_real(Key::Bank);
        let avail: Vec<bool> = (0..MAX_BEACONS)
            .map(|i| self.input_bool(Key::BeaconAvailable(i), true))
            .collect();
        let epoch = self.input_epoch();
        let status_before = self
            .engine
            .as_ref()
            .and_then(|e| e.nav())
            .map(|n| n.status().code());
        let guidance_inputs = self.guidance_inputs();
        let engine = self.engine.as_mut().ok_or(InstanceError::NoEngine)?;
        let report = match engine {
            Engine::Combined(c) => Self::step_combined(c, t, h, bank, &avail),
            Engine::Guided(g) => {
                let r = g.do_step(t, h, &avail)?;
                self.flown_bank = g.flight().flown_bank();
                return Ok(match r.ended {
                    Some((true, msg)) => {
                        self.info(&msg);
                        Status::Ok
                    }
                    Some((false, msg)) => {
                        self.warn(&msg);
                        Status::Warning
                    }
                    None => Status::Ok,
                });
            }
            Engine::Truth(ts) => ts.do_step(t, h, bank, &avail),
            Engine::Filter { nav, .. } => nav.do_step(t, h, bank, epoch.as_ref()),
            Engine::Guidance(g) => {
                let r = g.do_step(t, h, &guidance_inputs)?;
                if r.cycles > 1 {
                    self.report_multi_step(&format!(
                        "step from {t} by {h} runs {} guidance cycles, all with the inputs set before the step (use a communication step no longer than the guidance period for an estimate per cycle)",
                        r.cycles
                    ));
                }
                return Ok(Status::Ok);
            }
        }?;
        let mut status = Status::Ok;
        if self.model.has_truth() {
            self.flown_bank = Some(bank);
        }
        if self.model == Model::Truth && report.epochs > 1 {
            // Not a failure: system masters (OMSimulator) often step longer than a sensor period
            // and stop on fmi2Warning. The step succeeds; the outputs are the last epoch's.
            let msg = format!(
                "step from {t} by {h} spans {} measurement epochs; only the last is output (a \
                 filter fed from this FMU sees one epoch per step: use a communication step no \
                 longer than the fastest sensor period to pass every epoch)",
                report.epochs
            );
            self.report_multi_step(&msg);
        }
        if let Some(nav) = self.engine.as_ref().and_then(|e| e.nav())
            && let NavStatus::Failed { t, reason } = nav.status()
            && status_before != Some(2)
        {
            self.warn(&format!(
                "navigation filter failed at t = {t} s: {reason}; its estimate is frozen (nav_status = failed)"
            ));
            status = Status::Warning;
        }
        Ok(status)
    }

    /// Report a step that spans several epochs or guidance cycles: at warning level the first
    /// time, under `logEvents` after that.
    fn report_multi_step(&mut self, msg: &str) {
        if self.multi_epoch_reported {
            self.info(msg);
        } else {
            self.multi_epoch_reported = true;
            self.warn(msg);
        }
    }

    /// The guidance FMU's inputs.
    fn guidance_inputs(&self) -> GuidanceInputs {
        use crate::vars::Slot::Accel;
        let valid = (0..3).all(|k| self.input_bool(Key::MeasValid(Accel(k)), false));
        GuidanceInputs {
            est_x: std::array::from_fn(|i| self.input_real(Key::EstX(i))),
            est_t: self.input_real(Key::NavTime),
            nav_status: match self.value_of(Key::NavStatusCode) {
                Some(Value::Integer(c)) => *c,
                _ => 0,
            },
            accel: valid
                .then(|| std::array::from_fn(|k| self.input_real(Key::Meas(Accel(k as u8))))),
        }
    }

    /// Refuse, before anything changes, a guidance step whose cycles would fly inputs guidance
    /// cannot use ([`GuidanceEngine::check`]).
    pub(super) fn check_guidance_step(&self, t: f64, h: f64) -> Result<(), InstanceError> {
        if let Some(Engine::Guidance(g)) = &self.engine {
            g.check(t, h, &self.guidance_inputs())?;
        }
        Ok(())
    }
}

/// Check the guided FMU's `run` parameter.
pub(super) fn check_run(run: i32) -> Result<(), InstanceError> {
    if (0..=limits::MAX_RUN).contains(&run) {
        Ok(())
    } else {
        Err(InstanceError::Run {
            got: run,
            max: limits::MAX_RUN,
        })
    }
}
