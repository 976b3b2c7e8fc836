//! A safe FMU instance: the FMI 2.0 co-simulation state machine, variable access and the engine.
//!
//! Every method checks the calling sequence first; an illegal call is answered with
//! [`Status::Error`] and the message "Illegal call sequence", and leaves the instance as it was.
//! Bad arguments (unknown value references, a wrong type, NaN/Inf reals, a step at the wrong
//! communication point or past the stop time) are rejected the same way. Only a failure of the
//! simulation itself (non-finite truth) moves the instance to the error phase, from which
//! `reset`, `set_state` or freeing recovers.

mod engine;
mod outputs;
mod snapshot;

pub use engine::{Engine, InstanceError};

use crate::state::{Phase, StepRecord};
use crate::uri::UriError;
use crate::vars::{Causality, Key, Model, Slot, Type, Value, Var, guid_of, variables};
use entrynav::sim::engine::same_time;
use outputs::validate;
use std::collections::HashMap;
use std::path::PathBuf;

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

/// One FMU instance.
pub struct Instance {
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
    steps: Vec<StepRecord>,
    slot_channel: HashMap<Slot, usize>,
}

impl std::fmt::Debug for Instance {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Instance")
            .field("model", &self.model)
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

use Phase::*;

/// Phases in which fmi2GetXXX is legal.
const GET: &[Phase] = &[InitializationMode, StepComplete, Terminated, Error];
/// Phases in which FMU-state functions are legal.
pub(super) const STATE: &[Phase] = &[
    Instantiated,
    InitializationMode,
    StepComplete,
    Terminated,
    Error,
];

impl Instance {
    /// Instantiate: checks the name, the GUID and the resource location (an unusable location is
    /// an error only when a scenario file has to be read from it).
    pub fn new(
        name: &str,
        guid: &str,
        resource_location: Option<&str>,
        logging_on: bool,
        log: LogSink,
    ) -> Result<Instance, (LogSink, String)> {
        if name.trim().is_empty() {
            return Err((log, "fmi2Instantiate: the instance name is empty".into()));
        }
        let Some(model) = Model::from_guid(guid) else {
            return Err((
                log,
                format!(
                    "fmi2Instantiate: GUID '{guid}' does not match this FMU ({} {}, {} {}, {} {})",
                    Model::Combined.identifier(),
                    guid_of(Model::Combined),
                    Model::Filter.identifier(),
                    guid_of(Model::Filter),
                    Model::Truth.identifier(),
                    guid_of(Model::Truth)
                ),
            ));
        };
        let resources = match resource_location {
            None => Err(UriError::Missing),
            Some(loc) => crate::uri::resource_dir(loc),
        };
        let vars = variables(model);
        let values = vars.iter().map(|v| v.start.clone()).collect();
        let inputs = vars
            .iter()
            .enumerate()
            .filter(|(_, v)| v.causality == Causality::Input)
            .map(|(i, _)| i)
            .collect();
        let inst = Instance {
            model,
            name: name.to_string(),
            vars,
            values,
            inputs,
            resources,
            log,
            logging_on,
            enabled: vec![],
            phase: Instantiated,
            start_time: 0.0,
            stop_time: None,
            engine: None,
            steps: vec![],
            slot_channel: HashMap::new(),
        };
        inst.info(&format!(
            "instantiated {} ({})",
            model.identifier(),
            guid_of(model)
        ));
        Ok(inst)
    }

    /// The model.
    pub fn model(&self) -> Model {
        self.model
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
        self.warning(msg);
    }

    fn warning(&self, msg: &str) {
        (self.log)(Status::Warning, "logStatusWarning", msg);
    }

    fn info(&self, msg: &str) {
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

    /// Move to the error phase after an internal failure (a caught panic).
    pub fn poison(&mut self, msg: &str) -> Status {
        self.phase = Error;
        self.error(msg)
    }

    fn check(&self, func: &str, allowed: &[Phase]) -> Result<(), Status> {
        if allowed.contains(&self.phase) {
            Ok(())
        } else {
            Err(self.error(&format!(
                "{func}: Illegal call sequence (the instance is in state {}; allowed in {})",
                phase_name(self.phase),
                allowed
                    .iter()
                    .map(|p| phase_name(*p))
                    .collect::<Vec<_>>()
                    .join(", ")
            )))
        }
    }

    /// fmi2SetDebugLogging.
    pub fn set_debug_logging(&mut self, on: bool, categories: &[String]) -> Status {
        if let Err(s) = self.check("fmi2SetDebugLogging", STATE) {
            return s;
        }
        for c in categories {
            if !crate::xml::LOG_CATEGORIES.iter().any(|(n, _)| n == c) {
                return self.error(&format!(
                    "fmi2SetDebugLogging: unknown log category '{c}' (known: {})",
                    crate::xml::LOG_CATEGORIES.map(|(n, _)| n).join(", ")
                ));
            }
        }
        self.logging_on = on;
        self.enabled = categories.to_vec();
        Status::Ok
    }

    /// fmi2SetupExperiment.
    pub fn setup_experiment(&mut self, start: f64, stop: Option<f64>) -> Status {
        if let Err(s) = self.check("fmi2SetupExperiment", &[Instantiated]) {
            return s;
        }
        if !start.is_finite() || start != 0.0 {
            return self.error(&format!(
                "fmi2SetupExperiment: startTime must be 0 (the scenario's time origin), got {start}"
            ));
        }
        if let Some(t) = stop
            && !(t.is_finite() && t > start)
        {
            return self.error(&format!(
                "fmi2SetupExperiment: stopTime must be finite and after startTime, got {t}"
            ));
        }
        self.start_time = start;
        self.stop_time = stop;
        Status::Ok
    }

    /// fmi2EnterInitializationMode.
    pub fn enter_initialization_mode(&mut self) -> Status {
        if let Err(s) = self.check("fmi2EnterInitializationMode", &[Instantiated]) {
            return s;
        }
        self.phase = InitializationMode;
        Status::Ok
    }

    /// fmi2ExitInitializationMode: builds the engine from the parameters.
    pub fn exit_initialization_mode(&mut self) -> Status {
        if let Err(s) = self.check("fmi2ExitInitializationMode", &[InitializationMode]) {
            return s;
        }
        if let Err(e) = self.ensure_engine() {
            return self.error(&format!("fmi2ExitInitializationMode: {e}"));
        }
        self.phase = StepComplete;
        self.info("initialised");
        Status::Ok
    }

    /// fmi2Terminate.
    pub fn terminate(&mut self) -> Status {
        if let Err(s) = self.check("fmi2Terminate", &[StepComplete]) {
            return s;
        }
        self.phase = Terminated;
        Status::Ok
    }

    /// fmi2Reset: back to the instantiated state with the start values.
    pub fn reset(&mut self) -> Status {
        if let Err(s) = self.check("fmi2Reset", STATE) {
            return s;
        }
        self.values = self.vars.iter().map(|v| v.start.clone()).collect();
        self.phase = Instantiated;
        self.start_time = 0.0;
        self.stop_time = None;
        self.engine = None;
        self.steps.clear();
        Status::Ok
    }

    fn param_str(&self, key: Key) -> String {
        self.vars
            .iter()
            .zip(&self.values)
            .find(|(v, _)| v.key == key)
            .and_then(|(_, val)| match val {
                Some(Value::String(s)) => Some(s.clone()),
                _ => None,
            })
            .unwrap_or_default()
    }

    fn value_of(&self, key: Key) -> Option<&Value> {
        self.vars
            .iter()
            .position(|v| v.key == key)
            .and_then(|i| self.values[i].as_ref())
    }

    fn lookup(&self, func: &str, vr: u32, ty: Type) -> Result<usize, Status> {
        match self.vars.get(vr as usize) {
            Some(v) if v.ty == ty => Ok(vr as usize),
            Some(v) => Err(self.error(&format!(
                "{func}: value reference {vr} ('{}') is a {} variable, not {}",
                v.name,
                v.ty.xml(),
                ty.xml()
            ))),
            None => Err(self.error(&format!(
                "{func}: unknown value reference {vr} ({} has value references 0 to {})",
                self.model.identifier(),
                self.vars.len() - 1
            ))),
        }
    }

    /// fmi2GetReal / Integer / Boolean / String: the values of `vrs`, all of type `ty`.
    pub fn get(&mut self, func: &str, ty: Type, vrs: &[u32]) -> Result<Vec<Value>, Status> {
        self.check(func, GET)?;
        let mut idx = Vec::with_capacity(vrs.len());
        for vr in vrs {
            idx.push(self.lookup(func, *vr, ty)?);
        }
        if self.engine.is_none()
            && idx
                .iter()
                .any(|i| self.vars[*i].causality == Causality::Output)
            && let Err(e) = self.ensure_engine()
        {
            return Err(self.error(&format!("{func}: cannot compute outputs: {e}")));
        }
        Ok(idx
            .iter()
            .map(|&i| match &self.values[i] {
                Some(v) => v.clone(),
                None => self.output(self.vars[i].key),
            })
            .collect())
    }

    /// fmi2SetReal / Integer / Boolean / String.
    pub fn set(&mut self, func: &str, vrs: &[u32], values: Vec<Value>) -> Status {
        if let Err(s) = self.check(func, &[Instantiated, InitializationMode, StepComplete]) {
            return s;
        }
        if vrs.len() != values.len() {
            return self.error(&format!(
                "{func}: {} references but {} values",
                vrs.len(),
                values.len()
            ));
        }
        // Validate everything first: a rejected call changes nothing.
        for (vr, val) in vrs.iter().zip(&values) {
            let i = match self.lookup(func, *vr, val.ty()) {
                Ok(i) => i,
                Err(s) => return s,
            };
            let v = &self.vars[i];
            match v.causality {
                Causality::Output => {
                    return self.error(&format!(
                        "{func}: '{}' is an output and cannot be set",
                        v.name
                    ));
                }
                Causality::Parameter if self.phase == StepComplete => {
                    return self.error(&format!(
                        "{func}: parameter '{}' is fixed after initialisation (reset the instance to change it)",
                        v.name
                    ));
                }
                _ => {}
            }
            if let Err(e) = validate(v.key, val) {
                return self.error(&format!("{func}: '{}': {e}", v.name));
            }
        }
        for (vr, val) in vrs.iter().zip(values) {
            let i = *vr as usize;
            if self.vars[i].causality == Causality::Parameter
                && self.values[i].as_ref() != Some(&val)
            {
                self.engine = None;
            }
            self.values[i] = Some(val);
        }
        Status::Ok
    }

    fn input_bool(&self, key: Key) -> bool {
        matches!(self.value_of(key), Some(Value::Boolean(true)))
    }

    fn input_real(&self, key: Key) -> f64 {
        match self.value_of(key) {
            Some(Value::Real(x)) => *x,
            _ => 0.0,
        }
    }

    /// fmi2DoStep.
    pub fn do_step(&mut self, t: f64, h: f64) -> Status {
        if let Err(s) = self.check("fmi2DoStep", &[StepComplete]) {
            return s;
        }
        if !(t.is_finite() && h.is_finite()) || h <= 0.0 {
            return self.error(&format!(
                "fmi2DoStep: communication point {t} and step size {h} must be finite with a step > 0"
            ));
        }
        if let Some(stop) = self.stop_time
            && t + h > stop
            && !same_time(t + h, stop)
        {
            return self.error(&format!(
                "fmi2DoStep: the step from {t} by {h} ends after stopTime {stop}"
            ));
        }
        let Some(engine) = &self.engine else {
            return self.poison("fmi2DoStep: no engine (internal error)");
        };
        if !same_time(engine.time(), t) {
            return self.error(&format!(
                "fmi2DoStep: currentCommunicationPoint {t} is not the current time {} of the instance",
                engine.time()
            ));
        }
        let inputs: Vec<Value> = self
            .inputs
            .iter()
            .map(|&i| self.values[i].clone().unwrap_or(Value::Real(0.0)))
            .collect();
        match self.step_engine(t, h) {
            Ok(status) => {
                self.steps.push(StepRecord { t, h, inputs });
                status
            }
            Err(e) => {
                self.phase = Error;
                self.error(&format!("fmi2DoStep: {e}"))
            }
        }
    }

    /// Time of the last successful step (fmi2LastSuccessfulTime).
    pub fn last_successful_time(&self) -> f64 {
        self.engine
            .as_ref()
            .map(Engine::time)
            .unwrap_or(self.start_time)
    }

    /// Check a status query is legal.
    pub fn check_status_query(&self, func: &str) -> Result<(), Status> {
        self.check(func, &[StepComplete, Terminated])
    }

    /// Check an unsupported-capability call: legal sequence first, then "not supported".
    pub fn unsupported(&self, func: &str, allowed: &[Phase], what: &str) -> Status {
        if let Err(s) = self.check(func, allowed) {
            return s;
        }
        self.error(&format!("{func}: {what} is not supported by this FMU"))
    }
}
