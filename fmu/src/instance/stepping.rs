//! Building an instance's engine from its parameters (the scenario, the filter, the seed), the
//! work bounds of a step, and one communication step of the engine with the inputs set.

use super::engine::{Engine, InstanceError, check_run};
use super::guidance::{GuidanceEngine, GuidanceInputs};
use super::guided::GuidedEngine;
use super::machine::Instance;
use super::scenario::load_parameter_scenario;
use super::status::Status;
use crate::limits::{self, LimitError, STEP_CHUNK_TRUTH_STEPS};
use crate::vars::{Key, MAX_BEACONS, Model, Slot, Value};
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::Scenario;
use entrynav::sensors::MeasurementEpoch;
use entrynav::sim::engine::{
    EngineError, EntryCoSim, NavStatus, Navigator, StepReport, TruthSensors,
};
use std::sync::Arc;

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
