//! The FMI 2.0 co-simulation state machine: the calls that move between states (each checked
//! against its entry of the allowed-state table, [`super::allowed`]), fmi2DoStep and the status
//! queries.

use super::allowed::Operation;
use super::machine::Instance;
use super::status::Status;
use crate::limits::MAX_CATEGORIES;
use crate::state::{Phase, StepRecord};
use crate::xml::LOG_CATEGORIES;
use Phase::*;
use entrynav::sim::engine::same_time;
use std::sync::Arc;

/// The value type of a fmi2Get*Status function.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StatusType {
    /// fmi2GetStatus.
    Status,
    /// fmi2GetRealStatus.
    Real,
    /// fmi2GetIntegerStatus.
    Integer,
    /// fmi2GetBooleanStatus.
    Boolean,
    /// fmi2GetStringStatus.
    String,
}

impl StatusType {
    /// The function of this value type.
    pub fn function(self) -> Operation {
        match self {
            StatusType::Status => Operation::GetStatus,
            StatusType::Real => Operation::GetRealStatus,
            StatusType::Integer => Operation::GetIntegerStatus,
            StatusType::Boolean => Operation::GetBooleanStatus,
            StatusType::String => Operation::GetStringStatus,
        }
    }
}

/// An answer of a status query.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum StatusAnswer {
    /// fmi2LastSuccessfulTime.
    Real(f64),
    /// fmi2Terminated.
    Boolean(bool),
}

/// The fmi2StatusKind values: name and the type of the function that answers it.
const STATUS_KINDS: [(&str, StatusType); 4] = [
    ("fmi2DoStepStatus", StatusType::Status),
    ("fmi2PendingStatus", StatusType::String),
    ("fmi2LastSuccessfulTime", StatusType::Real),
    ("fmi2Terminated", StatusType::Boolean),
];

impl Instance {
    /// fmi2SetDebugLogging.
    pub fn set_debug_logging(&mut self, on: bool, categories: &[String]) -> Status {
        if let Err(s) = self.check(Operation::SetDebugLogging) {
            return s;
        }
        if categories.len() > MAX_CATEGORIES {
            return self.error(&format!(
                "fmi2SetDebugLogging: {} categories; the limit is {MAX_CATEGORIES}",
                categories.len()
            ));
        }
        for c in categories {
            if !LOG_CATEGORIES.iter().any(|(n, _)| n == c) {
                return self.error(&format!(
                    "fmi2SetDebugLogging: unknown log category '{c}' (known: {})",
                    LOG_CATEGORIES.map(|(n, _)| n).join(", ")
                ));
            }
        }
        self.logging_on = on;
        self.enabled = categories.to_vec();
        Status::Ok
    }

    /// fmi2SetupExperiment.
    pub fn setup_experiment(&mut self, start: f64, stop: Option<f64>) -> Status {
        if let Err(s) = self.check(Operation::SetupExperiment) {
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
        if let Err(s) = self.check(Operation::EnterInitializationMode) {
            return s;
        }
        self.phase = InitializationMode;
        Status::Ok
    }

    /// fmi2ExitInitializationMode: builds the engine from the parameters. If it cannot (a scenario
    /// that does not load, a filter that does not fit it), the instance enters the error state.
    pub fn exit_initialization_mode(&mut self) -> Status {
        if let Err(s) = self.check(Operation::ExitInitializationMode) {
            return s;
        }
        if let Err(e) = self.ensure_engine() {
            return self.poison(&format!(
                "fmi2ExitInitializationMode: {e} (the instance is now in the error state; fmi2Reset to start again)"
            ));
        }
        self.phase = StepComplete;
        self.info("initialised");
        Status::Ok
    }

    /// fmi2Terminate.
    pub fn terminate(&mut self) -> Status {
        if let Err(s) = self.check(Operation::Terminate) {
            return s;
        }
        self.phase = Terminated;
        Status::Ok
    }

    /// fmi2Reset: back to the instantiated state with the start values.
    pub fn reset(&mut self) -> Status {
        if let Err(s) = self.check(Operation::Reset) {
            return s;
        }
        self.values = self.vars.iter().map(|v| v.start.clone()).collect();
        self.phase = Instantiated;
        self.start_time = 0.0;
        self.stop_time = None;
        self.engine = None;
        self.steps.clear();
        self.log_full_at = None;
        self.flown_bank = None;
        Status::Ok
    }

    /// fmi2DoStep. A refused step (bad arguments, a request over a bound) changes nothing; a step
    /// in which the simulation fails moves the instance to the error state.
    pub fn do_step(&mut self, t: f64, h: f64) -> Status {
        if let Err(s) = self.check(Operation::DoStep) {
            return s;
        }
        if !(t.is_finite() && h.is_finite()) || h <= 0.0 || !(t + h).is_finite() {
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
        if let Err(e) = self.check_step_work(t, h) {
            return self.error(&format!(
                "fmi2DoStep: refused, the instance is unchanged: {e}"
            ));
        }
        if let Err(e) = self.check_guidance_step(t, h) {
            return self.error(&format!(
                "fmi2DoStep: refused, the instance is unchanged: {e}"
            ));
        }
        let inputs = self.step_inputs();
        match self.step_engine(t, h) {
            Ok(status) => {
                self.record(StepRecord { t, h, inputs });
                status
            }
            Err(e) => self.poison(&format!("fmi2DoStep: {e}")),
        }
    }

    /// The inputs of this step, shared with the previous step's record when unchanged.
    fn step_inputs(&self) -> Arc<[crate::vars::Value]> {
        let now: Vec<_> = self
            .inputs
            .iter()
            .map(|&i| {
                self.values[i]
                    .clone()
                    .unwrap_or(crate::vars::Value::Real(0.0))
            })
            .collect();
        match self.steps.last() {
            Some(last) if *last.inputs == *now => Arc::clone(&last.inputs),
            _ => Arc::from(now),
        }
    }

    /// Append a successful step to the replay log, unless the log is (or would get) larger than
    /// an FMU state may be: then recording stops and fmi2GetFMUstate refuses from then on.
    fn record(&mut self, r: StepRecord) {
        if self.log_full_at.is_some() {
            return;
        }
        // The rest of a state (header, GUID, every variable's value) stays under this reserve,
        // so a state whose log fits can always be serialized.
        const RESERVE: usize = 64 << 10;
        if self.steps.bytes() + self.steps.cost(&r) > crate::limits::MAX_STATE_BYTES - RESERVE {
            self.warn(&format!(
                "fmi2DoStep: the replay log of this run reached {} bytes at t = {}; fmi2GetFMUstate is unavailable from now on (the run continues)",
                self.steps.bytes(),
                r.t
            ));
            self.log_full_at = Some(r.t);
            return;
        }
        self.steps.push(r);
    }

    /// Time of the last successful step (fmi2LastSuccessfulTime).
    pub fn last_successful_time(&self) -> f64 {
        self.engine
            .as_ref()
            .map(super::engine::Engine::time)
            .unwrap_or(self.start_time)
    }

    /// A fmi2Get*Status query of `kind` through the function of value type `ty`: a value that is
    /// not an fmi2StatusKind, or the kind of another Get*Status function, is an illegal argument
    /// (fmi2Error); a status this FMU cannot give (the pending or asynchronous step status: steps
    /// are synchronous) is fmi2Discard.
    pub fn query_status(&self, kind: i32, ty: StatusType) -> Result<StatusAnswer, Status> {
        let func = ty.function();
        self.check(func)?;
        let Some((name, kind_ty)) = usize::try_from(kind).ok().and_then(|k| STATUS_KINDS.get(k))
        else {
            return Err(self.error(&format!(
                "{func}: {kind} is not an fmi2StatusKind (0 fmi2DoStepStatus, 1 fmi2PendingStatus, 2 fmi2LastSuccessfulTime, 3 fmi2Terminated)"
            )));
        };
        if *kind_ty != ty {
            return Err(self.error(&format!(
                "{func}: {name} is answered by {}, not by {func}",
                kind_ty.function()
            )));
        }
        match kind {
            2 => Ok(StatusAnswer::Real(self.last_successful_time())),
            3 => Ok(StatusAnswer::Boolean(false)),
            _ => {
                (self.log)(
                    Status::Discard,
                    "logStatusDiscard",
                    &format!(
                        "{func}: {name} is not available: this FMU has no asynchronous steps (canRunAsynchronuously = false)"
                    ),
                );
                Err(Status::Discard)
            }
        }
    }

    /// Check an unsupported-capability call: legal sequence first, then "not supported".
    pub fn unsupported(&self, f: Operation, what: &str) -> Status {
        if let Err(s) = self.check(f) {
            return s;
        }
        self.error(&format!("{f}: {what} is not supported by this FMU"))
    }

    /// fmi2CancelStep: steps are synchronous, so there is never a step to cancel (the table
    /// allows it in no phase of this FMU).
    pub fn cancel_step(&self) -> Status {
        match self.check(Operation::CancelStep) {
            Ok(()) => Status::Ok,
            Err(s) => s,
        }
    }
}
