//! A safe FMU instance: the FMI 2.0 co-simulation state machine, variable access and the engine.
//!
//! Every method checks the calling sequence first against the table of allowed states, one entry
//! per fmi2 function ([`Operation::allowed`]); an illegal call is answered with [`Status::Error`] and
//! the message "Illegal call sequence", and leaves the instance as it was. A *refused* call changes nothing either: a bad argument (unknown value
//! reference, a wrong type, NaN/Inf reals, a step at the wrong communication point or past the
//! stop time) or a request over a bound of [`crate::limits`]. A call that *starts and fails* —
//! fmi2ExitInitializationMode that cannot build the engine, a step in which the simulation
//! fails, fmi2SetFMUstate whose replay fails — moves the instance to the error state, from which
//! only fmi2Reset, fmi2SetFMUstate, fmi2FreeInstance and the queries lead on (FMI 2.0 §2.1.3).

mod allowed;
mod engine;
mod fmi3;
mod guidance;
mod guided;
mod lifecycle;
mod outputs;
mod scenario;
mod snapshot;
mod spec;
mod values;

pub use allowed::{Operation, Phases};
pub use engine::{Engine, InstanceError};
pub use fmi3::{Ref3, Type3};
pub use guidance::{GuidanceEngine, GuidanceInputs, GuidanceReport, GuidanceStepError};
pub use guided::{GuidedEngine, GuidedReport, GuidedStatus};
pub use lifecycle::{StatusAnswer, StatusType};
pub use scenario::{ScenarioFileError, load_resource_scenario};
pub use spec::resolve_spec;

use crate::state::{Phase, StepLog};
use crate::uri::UriError;
use crate::vars::{Causality, Model, ModelSpec, Slot, Value, Var};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;
use thiserror::Error;

/// fmi2Status.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Status {
    /// fmi2OK.
    Ok = 0,
    /// fmi2Warning.
    Warning = 1,
    /// fmi2Discard.
    Discard = 2,
    /// fmi2Error.
    Error = 3,
    /// fmi2Fatal.
    Fatal = 4,
}

/// Where log messages go: (status, category, message).
pub type LogSink = Box<dyn Fn(Status, &str, &str) + Send>;

/// Why fmi2Instantiate refuses.
#[derive(Debug, Error)]
pub enum InstantiateError {
    /// An empty instance name.
    #[error("fmi2Instantiate: the instance name is empty")]
    EmptyName,
    /// A GUID that is not the model's.
    #[error("fmi2Instantiate: GUID '{given}' does not match this FMU: {expected}")]
    Guid {
        /// The GUID given.
        given: String,
        /// What this binary accepts (and which model the given GUID belongs to, if any).
        expected: String,
    },
    /// A specific FMU whose embedded scenario cannot be loaded.
    #[error("fmi2Instantiate: the embedded scenario of {identifier} cannot be used: {reason}")]
    Embedded {
        /// The model identifier.
        identifier: String,
        /// Why.
        reason: String,
    },
}

/// One FMU instance.
pub struct Instance {
    spec: Arc<ModelSpec>,
    model: Model,
    name: String,
    vars: Vec<Var>,
    values: Vec<Option<Value>>,
    inputs: Vec<usize>,
    resources: Result<PathBuf, UriError>,
    log: LogSink,
    logging_on: bool,
    enabled: Vec<String>,
    phase: Phase,
    start_time: f64,
    stop_time: Option<f64>,
    engine: Option<Engine>,
    steps: StepLog,
    /// Time from which the replay log is no longer recorded (it would exceed
    /// [`crate::limits::MAX_STATE_BYTES`]); fmi2GetFMUstate refuses from then on.
    log_full_at: Option<f64>,
    slot_channel: HashMap<Slot, usize>,
    /// Whether a step spanning several sensor epochs was already reported at warning level (later
    /// ones are logged under `logEvents`).
    multi_epoch_reported: bool,
    /// The bank the truth flew over the last step (`truth_bank_angle`).
    flown_bank: Option<f64>,
}

impl std::fmt::Debug for Instance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Instance")
            .field("model", &self.spec.identifier())
            .field("name", &self.name)
            .field("phase", &self.phase)
            .finish()
    }
}

fn phase_name(p: Phase) -> &'static str {
    match p {
        Phase::Instantiated => "Instantiated",
        Phase::InitializationMode => "InitializationMode",
        Phase::StepComplete => "StepComplete",
        Phase::Terminated => "Terminated",
        Phase::Error => "Error",
    }
}

/// The model a GUID names when no binding restricts it: one of the generic models.
pub fn generic_spec(guid: &str) -> Result<Arc<ModelSpec>, InstantiateError> {
    match Model::from_guid(guid) {
        Some(m) => Ok(Arc::new(ModelSpec::generic(m))),
        None => Err(InstantiateError::Guid {
            given: guid.to_string(),
            expected: format!(
                "this library serves {}",
                Model::ALL
                    .map(|m| format!("{} {}", m.identifier(), crate::vars::guid_of(m)))
                    .join(", ")
            ),
        }),
    }
}

impl Instance {
    /// Instantiate `spec` as `name`: checks the name, that `guid` is the model's, and the resource
    /// location (an unusable location is an error only when a scenario file has to be read).
    pub fn new(
        spec: Arc<ModelSpec>,
        name: &str,
        guid: &str,
        resource_location: Option<&str>,
        logging_on: bool,
        log: LogSink,
    ) -> Result<Instance, (LogSink, InstantiateError)> {
        if name.trim().is_empty() {
            return Err((log, InstantiateError::EmptyName));
        }
        if guid != spec.guid() {
            let e = InstantiateError::Guid {
                given: guid.to_string(),
                expected: format!("{} has GUID {}", spec.identifier(), spec.guid()),
            };
            return Err((log, e));
        }
        let resources = match resource_location {
            None => Err(UriError::Missing),
            Some(loc) => crate::uri::resource_dir(loc),
        };
        let vars = spec.vars().to_vec();
        let values = vars.iter().map(|v| v.start.clone()).collect();
        let inputs = vars
            .iter()
            .enumerate()
            .filter(|(_, v)| v.causality == Causality::Input)
            .map(|(i, _)| i)
            .collect();
        let inst = Instance {
            model: spec.model(),
            spec,
            name: name.to_string(),
            vars,
            values,
            inputs,
            resources,
            log,
            logging_on,
            enabled: vec![],
            phase: Phase::Instantiated,
            start_time: 0.0,
            stop_time: None,
            engine: None,
            steps: StepLog::default(),
            log_full_at: None,
            slot_channel: HashMap::new(),
            multi_epoch_reported: false,
            flown_bank: None,
        };
        inst.info(&format!(
            "instantiated {} ({})",
            inst.spec.identifier(),
            inst.spec.guid()
        ));
        Ok(inst)
    }

    /// The model (the generic model, or the base of a specific one).
    pub fn model(&self) -> Model {
        self.model
    }

    /// The model with its table and GUID.
    pub fn spec(&self) -> &Arc<ModelSpec> {
        &self.spec
    }

    /// The instance name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The phase.
    pub fn phase(&self) -> Phase {
        self.phase
    }

    /// The engine, once built.
    pub fn engine(&self) -> Option<&Engine> {
        self.engine.as_ref()
    }

    /// Log an error and return [`Status::Error`].
    pub fn error(&self, msg: &str) -> Status {
        (self.log)(Status::Error, "logStatusError", msg);
        Status::Error
    }

    /// Log a warning.
    pub fn warn(&self, msg: &str) {
        (self.log)(Status::Warning, "logStatusWarning", msg);
    }

    pub(super) fn info(&self, msg: &str) {
        if self.logging_on
            && (self.enabled.is_empty()
                || self
                    .enabled
                    .iter()
                    .any(|c| c == "logEvents" || c == "logAll"))
        {
            (self.log)(Status::Ok, "logEvents", msg);
        }
    }

    /// Move to the error phase after a failure inside a call (a caught panic, a failed step).
    pub fn poison(&mut self, msg: &str) -> Status {
        self.phase = Phase::Error;
        self.error(msg)
    }

    /// Whether `f` may be called in the current phase ([`Operation::allowed`]); if not, the error is
    /// logged ("Illegal call sequence") and returned.
    pub fn check(&self, f: Operation) -> Result<(), Status> {
        self.check_as(f, f)
    }

    /// [`Instance::check`] of `f`'s table entry on behalf of the function `name` (an FMI 3.0
    /// function whose allowed states are those of `f`), which the message names.
    pub fn check_as(&self, f: Operation, name: impl std::fmt::Display) -> Result<(), Status> {
        let allowed = f.allowed();
        if allowed.contains(self.phase) {
            return Ok(());
        }
        let states: Vec<&str> = allowed.iter().map(phase_name).collect();
        let allowed_in = match states.is_empty() {
            true => "only in states this FMU never enters".to_string(),
            false => format!("in {}", states.join(", ")),
        };
        Err(self.error(&format!(
            "{name}: Illegal call sequence (the instance is in state {}; allowed {allowed_in})",
            phase_name(self.phase),
        )))
    }
}
