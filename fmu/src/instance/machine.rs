//! The [`Instance`]: its model and table, the values set, the resources folder, the log, the
//! phase of the FMI state machine, the engine once built and the replay log; its accessors, its
//! logging, and the check every call makes against the allowed-state table ([`super::allowed`]).

use super::allowed::Operation;
use super::engine::Engine;
use super::status::{InstantiateError, LogSink, Status};
use crate::state::{Phase, StepLog};
use crate::uri::UriError;
use crate::vars::{Causality, Model, ModelSpec, Slot, Value, Var};
use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::Arc;

/// One FMU instance.
pub struct Instance {
    pub(super) spec: Arc<ModelSpec>,
    pub(super) model: Model,
    pub(super) name: String,
    pub(super) vars: Vec<Var>,
    pub(super) values: Vec<Option<Value>>,
    pub(super) inputs: Vec<usize>,
    pub(super) resources: Result<PathBuf, UriError>,
    pub(super) log: LogSink,
    pub(super) logging_on: bool,
    pub(super) enabled: Vec<String>,
    pub(super) phase: Phase,
    pub(super) start_time: f64,
    pub(super) stop_time: Option<f64>,
    pub(super) engine: Option<Engine>,
    pub(super) steps: StepLog,
    /// Time from which the replay log is no longer recorded (it would exceed
    /// [`crate::limits::MAX_STATE_BYTES`]); fmi2GetFMUstate refuses from then on.
    pub(super) log_full_at: Option<f64>,
    pub(super) slot_channel: HashMap<Slot, usize>,
    /// Whether a step spanning several sensor epochs was already reported at warning level (later
    /// ones are logged under `logEvents`).
    pub(super) multi_epoch_reported: bool,
    /// The bank the truth flew over the last step (`truth_bank_angle`).
    pub(super) flown_bank: Option<f64>,
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
