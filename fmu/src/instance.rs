//! A safe FMU instance: the FMI 2.0 co-simulation state machine, variable access and the engine.
//!
//! Every method checks the calling sequence first; an illegal call is answered with
//! [`Status::Error`] and the message "Illegal call sequence", and leaves the instance as it was.
//! Bad arguments (unknown value references, a wrong type, NaN/Inf reals, a step at the wrong
//! communication point or past the stop time) are rejected the same way. Only a failure of the
//! simulation itself (non-finite truth) moves the instance to the error phase, from which
//! `reset`, `set_state` or freeing recovers.

use crate::state::{Phase, Snapshot, StepRecord};
use crate::vars::{
    Causality, Key, MAX_BEACONS, MAX_STATES, MAX_WEIGHTS, Model, Slot, Type, Value, Var, guid_of,
    variables,
};
use entrynav::estimation::nav::FilterKind;
use entrynav::frames::inertial_to_spherical;
use entrynav::scenario::{BUILTIN_NAMES, Scenario, ScenarioConfig};
use entrynav::sim::cosim::{CoSimError, EntryCoSim, NavigationCoSim, TruthSensors, same_time};
use entrynav::sim::{MeasurementEpoch, StopReason};
use std::collections::HashMap;
use std::path::{Path, PathBuf};
use std::sync::Arc;

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

/// The simulation behind an instance.
#[derive(Debug)]
pub enum Engine {
    /// Truth, sensors and filter.
    Combined(Box<EntryCoSim>),
    /// Truth and sensors.
    Truth(Box<TruthSensors>),
    /// Filter alone.
    Filter(Box<NavigationCoSim>),
}

impl Engine {
    fn scenario(&self) -> &Arc<Scenario> {
        match self {
            Engine::Combined(c) => c.truth().scenario(),
            Engine::Truth(t) => t.scenario(),
            Engine::Filter(f) => f.scenario(),
        }
    }

    fn truth(&self) -> Option<&TruthSensors> {
        match self {
            Engine::Combined(c) => Some(c.truth()),
            Engine::Truth(t) => Some(t),
            Engine::Filter(_) => None,
        }
    }

    fn nav(&self) -> Option<&NavigationCoSim> {
        match self {
            Engine::Combined(c) => Some(c.nav()),
            Engine::Filter(f) => Some(f),
            Engine::Truth(_) => None,
        }
    }

    /// Current communication point.
    pub fn time(&self) -> f64 {
        match self {
            Engine::Combined(c) => c.time(),
            Engine::Truth(t) => t.time(),
            Engine::Filter(f) => f.time(),
        }
    }
}

type R<T> = Result<T, String>;

/// One FMU instance.
pub struct Instance {
    model: Model,
    name: String,
    vars: Vec<Var>,
    values: Vec<Option<Value>>,
    inputs: Vec<usize>,
    resources: R<PathBuf>,
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
const STATE: &[Phase] = &[
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
            None => Err("no fmuResourceLocation was given".to_string()),
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

    fn load_scenario(&self) -> R<Arc<Scenario>> {
        let name = self.param_str(Key::Scenario);
        let name = name.trim();
        if BUILTIN_NAMES.contains(&name) {
            let cfg = ScenarioConfig::builtin(name).map_err(|e| e.to_string())?;
            let sc = Scenario::build(cfg, &|p: &str| Err(format!("cannot read {p}")))
                .map_err(|e| e.to_string())?;
            return Ok(Arc::new(sc));
        }
        let path = if Path::new(name).is_absolute() {
            PathBuf::from(name)
        } else {
            let dir = self.resources.as_ref().map_err(|e| {
                format!(
                    "scenario '{name}' is not a built-in ({}) and the resources folder is unusable: {e}",
                    BUILTIN_NAMES.join(", ")
                )
            })?;
            dir.join(name)
        };
        let text = std::fs::read_to_string(&path).map_err(|e| {
            format!(
                "scenario '{name}' is neither a built-in ({}) nor a readable file ({}: {e})",
                BUILTIN_NAMES.join(", "),
                path.display()
            )
        })?;
        let cfg = ScenarioConfig::from_toml_str(&text, &path.display().to_string())
            .map_err(|e| e.to_string())?;
        let dir = path.parent().map(Path::to_path_buf).unwrap_or_default();
        let load = move |p: &str| -> Result<String, String> {
            let f = if Path::new(p).is_absolute() {
                PathBuf::from(p)
            } else {
                dir.join(p)
            };
            std::fs::read_to_string(&f).map_err(|e| format!("cannot read {}: {e}", f.display()))
        };
        Ok(Arc::new(
            Scenario::build(cfg, &load).map_err(|e| e.to_string())?,
        ))
    }

    fn build_engine(&self) -> R<Engine> {
        let scenario = self.load_scenario()?;
        let seed = match self.value_of(Key::Seed) {
            Some(Value::Integer(s)) => *s as u64,
            _ => 0,
        };
        let dispersed = matches!(self.value_of(Key::Dispersed), Some(Value::Boolean(true)));
        let kind = || FilterKind::parse(&self.param_str(Key::Filter)).map_err(|e| e.to_string());
        let err = |e: CoSimError| e.to_string();
        let n_beacons = scenario.beacons.len();
        if n_beacons > MAX_BEACONS {
            self.warning(&format!(
                "scenario has {n_beacons} beacons; only the first {MAX_BEACONS} have FMU variables"
            ));
        }
        Ok(match self.model {
            Model::Combined => Engine::Combined(Box::new(
                EntryCoSim::new(scenario, kind()?, seed, dispersed).map_err(err)?,
            )),
            Model::Filter => Engine::Filter(Box::new(
                NavigationCoSim::new(scenario, kind()?, seed, dispersed).map_err(err)?,
            )),
            Model::Truth => Engine::Truth(Box::new(TruthSensors::new(scenario, seed, dispersed))),
        })
    }

    fn ensure_engine(&mut self) -> R<()> {
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

    fn step_engine(&mut self, t: f64, h: f64) -> R<Status> {
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
        let engine = self.engine.as_mut().ok_or("no engine")?;
        let report = match engine {
            Engine::Combined(c) => c.do_step(t, h, bank, &avail),
            Engine::Truth(ts) => ts.do_step(t, h, bank, &avail),
            Engine::Filter(f) => f.do_step(t, h, bank, epoch.as_ref()),
        }
        .map_err(|e| e.to_string())?;
        let mut status = Status::Ok;
        if self.model == Model::Truth && report.epochs > 1 {
            self.warning(&format!(
                "step from {t} by {h} spans {} measurement epochs; only the last is output (use a communication step no longer than the fastest sensor period)",
                report.epochs
            ));
            status = Status::Warning;
        }
        if let Some(nav) = self.engine.as_ref().and_then(|e| e.nav())
            && let entrynav::sim::cosim::NavStatus::Failed { t, reason } = nav.status()
            && status_before != Some(2)
        {
            self.warning(&format!(
                "navigation filter failed at t = {t} s: {reason}; its estimate is frozen (nav_status = 2)"
            ));
            status = Status::Warning;
        }
        Ok(status)
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

    /// fmi2GetFMUstate.
    pub fn get_state(&self) -> Result<Snapshot, Status> {
        self.check("fmi2GetFMUstate", STATE)?;
        Ok(Snapshot {
            model: self.model,
            guid: guid_of(self.model),
            phase: self.phase,
            start_time: self.start_time,
            stop_time: self.stop_time,
            values: self.values.clone(),
            steps: self.steps.clone(),
        })
    }

    /// Check a state-function call is legal.
    pub fn check_state_call(&self, func: &str) -> Result<(), Status> {
        self.check(func, STATE)
    }

    /// Check a snapshot fits this instance (model, GUID, table).
    pub fn check_snapshot(&self, func: &str, s: &Snapshot) -> Result<(), Status> {
        if s.model != self.model || s.guid != guid_of(self.model) {
            return Err(self.error(&format!(
                "{func}: the FMU state belongs to {} {}, not to this {} instance",
                s.model.identifier(),
                s.guid,
                self.model.identifier()
            )));
        }
        let types_ok = s.values.len() == self.vars.len()
            && s.values.iter().zip(&self.vars).all(|(v, var)| match v {
                None => !var.settable(),
                Some(v) => var.settable() && v.ty() == var.ty,
            })
            && s.steps.iter().all(|st| {
                st.inputs.len() == self.inputs.len()
                    && st
                        .inputs
                        .iter()
                        .zip(&self.inputs)
                        .all(|(v, &i)| v.ty() == self.vars[i].ty)
            });
        if !types_ok {
            return Err(self.error(&format!(
                "{func}: the FMU state's values do not match the variables of {}",
                self.model.identifier()
            )));
        }
        Ok(())
    }

    /// fmi2SetFMUstate: rebuild and replay.
    pub fn set_state(&mut self, s: &Snapshot) -> Status {
        if let Err(st) = self.check("fmi2SetFMUstate", STATE) {
            return st;
        }
        if let Err(st) = self.check_snapshot("fmi2SetFMUstate", s) {
            return st;
        }
        self.engine = None;
        self.steps.clear();
        self.start_time = s.start_time;
        self.stop_time = s.stop_time;
        self.values = s.values.clone();
        self.phase = s.phase;
        let needs_engine = matches!(s.phase, StepComplete | Terminated) || !s.steps.is_empty();
        if needs_engine {
            if let Err(e) = self.ensure_engine() {
                self.phase = Error;
                return self.error(&format!("fmi2SetFMUstate: cannot rebuild the engine: {e}"));
            }
            let current: Vec<Option<Value>> = self.values.clone();
            for st in &s.steps {
                for (&i, v) in self.inputs.iter().zip(&st.inputs) {
                    self.values[i] = Some(v.clone());
                }
                if let Err(e) = self.step_engine(st.t, st.h) {
                    self.phase = Error;
                    self.values = current;
                    return self.error(&format!(
                        "fmi2SetFMUstate: replay failed at t = {}: {e}",
                        st.t
                    ));
                }
                self.steps.push(st.clone());
            }
            self.values = current;
        }
        self.info(&format!(
            "FMU state restored ({} steps replayed)",
            s.steps.len()
        ));
        Status::Ok
    }

    fn output(&self, key: Key) -> Value {
        let Some(engine) = &self.engine else {
            return Value::Real(f64::NAN);
        };
        let scenario = engine.scenario();
        let nan = f64::NAN;
        let real = Value::Real;
        if let Some(ts) = engine.truth() {
            let o = ts.outputs();
            let nb = scenario.beacons.len();
            match key {
                Key::TruthSph(k) => return real(o.sample.spherical[k]),
                Key::TruthAltitude => return real(o.sample.altitude),
                Key::TruthDensity => return real(o.sample.density),
                Key::TruthDynamicPressure => return real(o.sample.dynamic_pressure),
                Key::TruthHeating => return real(o.sample.heating),
                Key::TruthAeroAccel => return real(o.sample.aero_accel),
                Key::TruthSensedAccel(k) => return real(o.sensed_accel[k]),
                Key::BeaconRange(i) => return real(if i < nb { o.ranges[i] } else { 0.0 }),
                Key::BeaconVisible(i) => {
                    return Value::Boolean(i < nb && o.sample.visible[i]);
                }
                Key::TruthStop => {
                    return Value::Integer(match ts.stop() {
                        None => 0,
                        Some(StopReason::Duration) => 1,
                        Some(StopReason::StopSpeed) => 2,
                        Some(StopReason::Ground) => 3,
                    });
                }
                Key::NBeacons => return Value::Integer(nb as i32),
                Key::MeasEpoch => return Value::Boolean(ts.last_epoch().is_some()),
                Key::MeasTime => return real(ts.last_epoch().map(|e| e.t).unwrap_or(0.0)),
                Key::Meas(s) | Key::MeasValid(s) => {
                    let v = ts
                        .last_epoch()
                        .zip(self.slot_channel.get(&s))
                        .and_then(|(e, &c)| e.values[c]);
                    return if matches!(key, Key::Meas(_)) {
                        real(v.unwrap_or(0.0))
                    } else {
                        Value::Boolean(v.is_some())
                    };
                }
                _ => {}
            }
        }
        if let Some(nav) = engine.nav() {
            let est = nav.estimate();
            let n = est.x.len();
            let slot = |v: &[f64], i: usize| real(if i < n { v[i] } else { 0.0 });
            match key {
                Key::NavTime => return real(est.t),
                Key::NavStatus => return Value::Integer(nav.status().code()),
                Key::NStates => return Value::Integer(n as i32),
                Key::EstX(i) => return slot(&est.x, i),
                Key::EstSigma(i) => return slot(&est.sigma, i),
                Key::EstSph(k) => {
                    let fm = &scenario.filter_model;
                    let x = &est.x;
                    let s = if fm.kind.is_cartesian() {
                        inertial_to_spherical(
                            &[x[0], x[1], x[2]],
                            &[x[3], x[4], x[5]],
                            est.t,
                            fm.planet.rotation_rate,
                        )
                    } else {
                        [x[0], x[1], x[2], x[3], x[4], x[5]]
                    };
                    return real(s[k]);
                }
                Key::EstDensity => return real(est.density.unwrap_or(nan)),
                Key::Nis => return real(est.info.nis.unwrap_or(nan)),
                Key::NMeas => return Value::Integer(est.info.n_meas as i32),
                Key::Weight(i) => {
                    return real(
                        est.info
                            .weights
                            .as_ref()
                            .and_then(|w| w.get(i).copied())
                            .unwrap_or(0.0),
                    );
                }
                Key::NWeights => {
                    let nw = nav_weights(nav);
                    return Value::Integer(nw.min(MAX_WEIGHTS) as i32);
                }
                _ => {}
            }
        }
        if let Engine::Combined(c) = engine {
            let j = c.judgement();
            let n = j.err.len();
            let slot = |v: &[f64], i: usize| real(if i < n { v[i] } else { 0.0 });
            match key {
                Key::TruthX(i) => return slot(&j.truth, i),
                Key::Err(i) => return slot(&j.err, i),
                Key::Nees => return real(j.nees.map(|x| x.0).unwrap_or(nan)),
                Key::NeesDof => return Value::Integer(j.nees.map(|x| x.1 as i32).unwrap_or(0)),
                Key::NavTruthDensity => return real(j.density_true),
                _ => {}
            }
        }
        let _ = MAX_STATES;
        match self.vars.iter().find(|v| v.key == key).map(|v| v.ty) {
            Some(Type::Integer) => Value::Integer(0),
            Some(Type::Boolean) => Value::Boolean(false),
            Some(Type::String) => Value::String(String::new()),
            _ => real(nan),
        }
    }
}

fn nav_weights(nav: &NavigationCoSim) -> usize {
    nav.estimate()
        .info
        .weights
        .as_ref()
        .map(Vec::len)
        .unwrap_or(0)
}

/// Check a value before it is stored.
fn validate(key: Key, v: &Value) -> R<()> {
    match (key, v) {
        (_, Value::Real(x)) if !x.is_finite() => Err(format!("{x} is not a finite number")),
        (Key::Seed, Value::Integer(s)) if *s < 0 => Err(format!("seed must be >= 0, got {s}")),
        (Key::Filter, Value::String(s)) => {
            FilterKind::parse(s).map(|_| ()).map_err(|e| e.to_string())
        }
        (Key::Scenario, Value::String(s)) if s.trim().is_empty() => {
            Err("the scenario name is empty".into())
        }
        _ => Ok(()),
    }
}
