//! The simulation behind an instance: which engine a model runs, the scenario it is built from
//! (see [`super::scenario`]), the work bounds of a step, and one communication step.

use super::guidance::{GuidanceEngine, GuidanceStepError};
use super::guided::GuidedEngine;
use super::scenario::ScenarioFileError;
use crate::limits::{self, LimitError};
use entrynav::estimation::nav::NavError;
use entrynav::scenario::Scenario;
use entrynav::sensors::Channel;
use entrynav::sim::engine::{EngineError, EntryCoSim, Navigator, TruthSensors};
use entrynav::sim::guided::GuidedRunError;
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
