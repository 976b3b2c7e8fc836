//! The simulation behind an instance: which engine a model runs, the scenario it is built from
//! (through the one scenario loader), and one communication step of it.

use super::Instance;
use super::Status;
use crate::uri::UriError;
use crate::vars::{Key, MAX_BEACONS, Model, Slot, Value};
use entrynav::estimation::nav::{FilterKind, NavError};
use entrynav::scenario::{BUILTIN_NAMES, Scenario};
use entrynav::sensors::MeasurementEpoch;
use entrynav::sim::engine::{EngineError, EntryCoSim, NavStatus, Navigator, TruthSensors};
use entrynav_loader::{Base, LoadError};
use std::sync::Arc;
use thiserror::Error;

/// Why an instance cannot build or step its engine, or refuses a value.
#[derive(Debug, Error)]
pub enum InstanceError {
    /// The scenario could not be loaded.
    #[error(transparent)]
    Load(#[from] LoadError),
    /// A scenario file name with no usable resources folder to find it in.
    #[error(
        "scenario '{name}' is not a built-in ({builtins}) and the resources folder is unusable: {reason}"
    )]
    NoResources {
        /// The `scenario` parameter.
        name: String,
        /// Comma-separated built-in names.
        builtins: String,
        /// Why the resources folder is unusable.
        reason: UriError,
    },
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
    /// No engine where one must exist (an internal error).
    #[error("no engine")]
    NoEngine,
}

/// The simulation behind an instance.
#[derive(Debug)]
pub enum Engine {
    /// Truth, sensors and filter.
    Combined(Box<EntryCoSim>),
    /// Truth and sensors.
    Truth(Box<TruthSensors>),
    /// Filter alone.
    Filter(Arc<Scenario>, Box<Navigator>),
}

impl Engine {
    pub(super) fn scenario(&self) -> &Arc<Scenario> {
        match self {
            Engine::Combined(c) => c.truth().scenario(),
            Engine::Truth(t) => t.scenario(),
            Engine::Filter(s, _) => s,
        }
    }

    pub(super) fn truth(&self) -> Option<&TruthSensors> {
        match self {
            Engine::Combined(c) => Some(c.truth()),
            Engine::Truth(t) => Some(t),
            Engine::Filter(..) => None,
        }
    }

    pub(super) fn nav(&self) -> Option<&Navigator> {
        match self {
            Engine::Combined(c) => Some(c.nav()),
            Engine::Filter(_, f) => Some(f),
            Engine::Truth(_) => None,
        }
    }

    /// Current communication point.
    pub fn time(&self) -> f64 {
        match self {
            Engine::Combined(c) => c.time(),
            Engine::Truth(t) => t.time(),
            Engine::Filter(_, f) => f.time(),
        }
    }
}

impl Instance {
    /// The scenario named by the `scenario` parameter: a built-in, or a file in the FMU's
    /// resources folder (or an absolute path).
    fn load_scenario(&self) -> Result<Arc<Scenario>, InstanceError> {
        let name = self.param_str(Key::Scenario);
        let name = name.trim();
        let base = match &self.resources {
            Ok(dir) => Base::Folder(dir),
            Err(reason) => {
                let relative =
                    !BUILTIN_NAMES.contains(&name) && !std::path::Path::new(name).is_absolute();
                if relative {
                    return Err(InstanceError::NoResources {
                        name: name.to_string(),
                        builtins: BUILTIN_NAMES.join(", "),
                        reason: reason.clone(),
                    });
                }
                Base::Nowhere
            }
        };
        Ok(Arc::new(entrynav_loader::load(name, &[], base)?))
    }

    fn build_engine(&self) -> Result<Engine, InstanceError> {
        let scenario = self.load_scenario()?;
        let seed = match self.value_of(Key::Seed) {
            Some(Value::Integer(s)) => *s as u64,
            _ => 0,
        };
        let dispersed = matches!(self.value_of(Key::Dispersed), Some(Value::Boolean(true)));
        let kind = || FilterKind::parse(&self.param_str(Key::Filter));
        let n_beacons = scenario.beacons.len();
        if n_beacons > MAX_BEACONS {
            self.warning(&format!(
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
                Engine::Filter(scenario, Box::new(nav))
            }
            Model::Truth => Engine::Truth(Box::new(TruthSensors::new(scenario, seed, dispersed))),
        })
    }

    pub(super) fn ensure_engine(&mut self) -> Result<(), InstanceError> {
        if self.engine.is_none() {
            let e = self.build_engine()?;
            self.slot_channel = e
                .scenario()
                .channels
                .iter()
                .enumerate()
                .filter_map(|(i, c)| Slot::of(c.channel).map(|s| (s, i)))
                .collect();
            self.engine = Some(e);
        }
        Ok(())
    }

    pub(super) fn step_engine(&mut self, t: f64, h: f64) -> Result<Status, InstanceError> {
        let bank = self.input_real(Key::Bank);
        let avail: Vec<bool> = (0..MAX_BEACONS)
            .map(|i| self.input_bool(Key::BeaconAvailable(i)))
            .collect();
        let epoch = (self.model == Model::Filter && self.input_bool(Key::MeasEpoch)).then(|| {
            let n = self
                .engine
                .as_ref()
                .map(|e| e.scenario().channels.len())
                .unwrap_or(0);
            let mut values = vec![None; n];
            for (slot, &c) in &self.slot_channel {
                if self.input_bool(Key::MeasValid(*slot)) {
                    values[c] = Some(self.input_real(Key::Meas(*slot)));
                }
            }
            MeasurementEpoch {
                t: self.input_real(Key::MeasTime),
                values,
            }
        });
        let status_before = self
            .engine
            .as_ref()
            .and_then(|e| e.nav())
            .map(|n| n.status().code());
        let engine = self.engine.as_mut().ok_or(InstanceError::NoEngine)?;
        let report = match engine {
            Engine::Combined(c) => c.do_step(t, h, bank, &avail),
            Engine::Truth(ts) => ts.do_step(t, h, bank, &avail),
            Engine::Filter(_, f) => f.do_step(t, h, bank, epoch.as_ref()),
        }?;
        let mut status = Status::Ok;
        if self.model == Model::Truth && report.epochs > 1 {
            self.warning(&format!(
                "step from {t} by {h} spans {} measurement epochs; only the last is output (use a communication step no longer than the fastest sensor period)",
                report.epochs
            ));
            status = Status::Warning;
        }
        if let Some(nav) = self.engine.as_ref().and_then(|e| e.nav())
            && let NavStatus::Failed { t, reason } = nav.status()
            && status_before != Some(2)
        {
            self.warning(&format!(
                "navigation filter failed at t = {t} s: {reason}; its estimate is frozen (nav_status = 2)"
            ));
            status = Status::Warning;
        }
        Ok(status)
    }
}
