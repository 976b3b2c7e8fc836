//! The fuzzer's model of an instance: the FMI 2.0 co-simulation state machine as the FMU
//! implements it, the parameters and inputs it was given, and what every call must answer.

use super::super::*;
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::{Scenario, ScenarioConfig};
use mars_entry_nav::ModelSpec;
use mars_entry_nav::vars::{
    DEFAULT_FILTER, DEFAULT_SCENARIO, DEFAULT_SEED, GUIDED_FILTER, GUIDED_SCENARIO_FILE,
};
use std::collections::HashMap;

/// The phases of the FMI 2.0 co-simulation state machine.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum St {
    Instantiated,
    Init,
    Step,
    Terminated,
    Error,
}

/// What a call must answer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Expect {
    /// fmi2OK.
    Ok,
    /// fmi2OK or fmi2Warning.
    OkOrWarning,
    /// fmi2Discard.
    Discard,
    /// fmi2Error, and the instance is unchanged (an illegal call or a refused request).
    Refused,
    /// fmi2Error, and the instance is in the error state afterwards (a call that failed).
    Fails,
}

impl Expect {
    pub(super) fn accepts(self, status: i32) -> bool {
        match self {
            Expect::Ok => status == 0,
            Expect::OkOrWarning => status == 0 || status == 1,
            Expect::Discard => status == 2,
            Expect::Refused | Expect::Fails => status == 3,
        }
    }
}

/// The parameters an instance of `spec` starts with, when they are not the generic defaults:
/// the embedded scenario and default filter of a specific FMU, the guided scenario and filter of
/// `MarsEntryNavGuided` (shared with the FMI 3.0 fuzzer).
pub(in crate::fmu) fn start_params(spec: &ModelSpec) -> Option<(&str, &'static str)> {
    match spec.specific() {
        Some(sp) => Some((sp.scenario.config.name.as_str(), sp.filter.name())),
        None if spec.model() == Model::Guided => Some((GUIDED_SCENARIO_FILE, GUIDED_FILTER)),
        None => None,
    }
}

/// Scenario timing and which filters fit, per built-in scenario (shared with the FMI 3.0
/// fuzzer).
pub(in crate::fmu) struct Scenarios {
    pub(in crate::fmu) timing: HashMap<String, (f64, f64)>,
    pub(in crate::fmu) fits: HashMap<String, Vec<&'static str>>,
    /// The scenarios the guided FMU can fly (a `[guidance]` section and the accelerometers).
    pub(in crate::fmu) guided: Vec<String>,
}

impl Scenarios {
    /// The built-in scenarios, and the embedded one of a specific FMU.
    pub(in crate::fmu) fn new(
        specific: Option<&mars_entry_nav::vars::Specific>,
    ) -> Result<Scenarios> {
        let mut all = Vec::new();
        for name in BUILTIN_NAMES {
            let s = Scenario::build(ScenarioConfig::builtin(name)?, &entrynav::files::no_files)?;
            all.push((name.to_string(), Arc::new(s)));
        }
        if let Some(sp) = specific {
            all.push((sp.scenario.config.name.clone(), Arc::clone(&sp.scenario)));
        }
        // The guided scenario file every generic FMU ships (the default of the guided models).
        all.push((
            GUIDED_SCENARIO_FILE.to_string(),
            Arc::new(mars_entry_nav::vars::guided_scenario()?),
        ));
        let (mut timing, mut fits, mut guided) = (HashMap::new(), HashMap::new(), Vec::new());
        for (name, s) in all {
            if s.config.guidance.is_some()
                && entrynav::sim::guided::accel_slots(&s.onboard).is_some()
            {
                guided.push(name.clone());
            }
            let t = &s.config.timing;
            timing.insert(name.clone(), (t.duration_s, s.onboard.filter_step_s));
            let ok: Vec<&'static str> = FilterKind::ALL
                .into_iter()
                .filter(|k| k.misfit(&s.onboard).is_none())
                .map(FilterKind::name)
                .collect();
            fits.insert(name, ok);
        }
        Ok(Scenarios {
            timing,
            fits,
            guided,
        })
    }
}

/// The model of one instance (everything fmi2GetFMUstate saves).
#[derive(Debug, Clone)]
pub(super) struct Sim {
    pub(super) st: St,
    /// The current communication point.
    pub(super) time: f64,
    pub(super) stop: Option<f64>,
    /// An engine exists (built by initialisation or by an output read in initialisation mode).
    pub(super) engine: bool,
    /// A step succeeded since the last reset (an FMU state then replays into an engine).
    pub(super) stepped: bool,
    pub(super) scenario: String,
    pub(super) filter: String,
    pub(super) seed: i32,
    pub(super) meas_epoch: bool,
    pub(super) meas_time: f64,
}

impl Sim {
    pub(super) fn new(specific: Option<(&str, &str)>) -> Sim {
        let (scenario, filter) = specific.unwrap_or((DEFAULT_SCENARIO, DEFAULT_FILTER));
        Sim {
            st: St::Instantiated,
            time: 0.0,
            stop: None,
            engine: false,
            stepped: false,
            scenario: scenario.to_string(),
            filter: filter.to_string(),
            seed: DEFAULT_SEED,
            meas_epoch: false,
            meas_time: 0.0,
        }
    }

    /// Whether the parameters give an engine: a built-in scenario and (for a model with a
    /// filter) a filter that fits it.
    pub(super) fn params_ok(&self, sc: &Scenarios, model: Model) -> bool {
        let Some(fits) = sc.fits.get(self.scenario.trim()) else {
            return false;
        };
        (!model.has_filter() || fits.contains(&self.filter.trim()))
            && (model != Model::Guided || sc.guided.iter().any(|g| g == self.scenario.trim()))
    }

    /// What fmi2Get* of `vars` answers.
    pub(super) fn get(
        &self,
        sc: &Scenarios,
        model: Model,
        vars: &[Option<&Var>],
        ty: Type,
    ) -> Expect {
        let legal = matches!(self.st, St::Init | St::Step | St::Terminated | St::Error)
            && vars.iter().all(|v| v.is_some_and(|v| v.ty == ty));
        if !legal {
            return Expect::Refused;
        }
        let outputs = vars
            .iter()
            .any(|v| v.is_some_and(|v| v.causality == Causality::Output));
        if outputs && !self.engine && !self.params_ok(sc, model) {
            return Expect::Refused;
        }
        Expect::Ok
    }

    /// What fmi2Set* of `v` to `x` answers (`valid`: the value passes the FMU's checks).
    pub(super) fn set(&self, v: Option<&Var>, ty: Type, valid: bool) -> Expect {
        let Some(v) = v else {
            return Expect::Refused;
        };
        let phase_ok = match v.causality {
            Causality::Input => matches!(self.st, St::Instantiated | St::Init | St::Step),
            Causality::Parameter => matches!(self.st, St::Instantiated | St::Init),
            Causality::Output => false,
        };
        if phase_ok && v.ty == ty && valid {
            Expect::Ok
        } else {
            Expect::Refused
        }
    }

    /// What fmi2DoStep(t, h) answers, given the filter FMU's last processed epoch `nav`
    /// (time, failed) read just before.
    pub(super) fn do_step(
        &self,
        sc: &Scenarios,
        model: Model,
        t: f64,
        h: f64,
        nav: Option<(f64, bool)>,
    ) -> Expect {
        if self.st != St::Step
            || !(t.is_finite() && h.is_finite() && h > 0.0 && (t + h).is_finite())
            || !same_time(t, self.time)
        {
            return Expect::Refused;
        }
        if let Some(stop) = self.stop
            && t + h > stop
            && !same_time(t + h, stop)
        {
            return Expect::Refused;
        }
        if model == Model::Filter
            && self.meas_epoch
            && let Some((last, failed)) = nav
            && let Some(&(duration, step)) = sc.timing.get(&self.scenario)
        {
            let processed = !failed && self.meas_time > last && self.meas_time <= t + h + 1e-9;
            let substeps = ((self.meas_time - last) / step).ceil();
            if processed && (substeps > 100_000.0 || self.meas_time > duration * (1.0 + 1e-9)) {
                return Expect::Refused;
            }
        }
        Expect::OkOrWarning
    }
}

/// Whether two communication points are the same instant (as the FMU decides it).
pub(super) fn same_time(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1.0)
}

/// What fmi2Get*Status of `kind` through the function of value type `ty` answers
/// (0 GetStatus, 1 GetRealStatus, 2 GetIntegerStatus, 3 GetBooleanStatus, 4 GetStringStatus).
pub(super) fn status_query(st: St, function: usize, kind: i32) -> Expect {
    if !matches!(st, St::Step | St::Terminated) {
        return Expect::Refused;
    }
    // The function that answers each fmi2StatusKind.
    let owner = match kind {
        0 => 0,
        1 => 4,
        2 => 1,
        3 => 3,
        _ => return Expect::Refused,
    };
    if owner != function {
        return Expect::Refused;
    }
    match kind {
        0 | 1 => Expect::Discard,
        _ => Expect::Ok,
    }
}
