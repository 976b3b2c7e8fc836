//! The fuzzer's model of an instance, the same for both FMI versions: the co-simulation state
//! machine this FMU has (*Instantiated*, *Initialization Mode*, *Step Mode* — FMI 2.0's
//! *stepComplete* —, *Terminated*, the error state; no event mode), the parameters and inputs it
//! was given, and what every call must answer.

use super::scenarios::Scenarios;
use super::variables::{Variable, What};
use entrynav_fmu::instance::Type3;
use entrynav_fmu::limits::MAX_PREDICTION_SUBSTEPS;
use entrynav_fmu::vars::{Causality, DEFAULT_FILTER, DEFAULT_SCENARIO, DEFAULT_SEED, Model, Var};

/// The states of the co-simulation state machine.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum St {
    Instantiated,
    Init,
    Step,
    Terminated,
    Error,
}

impl St {
    /// Where the getters are allowed.
    pub(super) fn readable(self) -> bool {
        matches!(self, St::Init | St::Step | St::Terminated | St::Error)
    }

    /// Where the setters are allowed.
    pub(super) fn writable(self) -> bool {
        matches!(self, St::Instantiated | St::Init | St::Step)
    }
}

/// What a call must answer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Expect {
    /// OK.
    Ok,
    /// OK or Warning.
    OkOrWarning,
    /// Discard (an FMI 2.0 status query this FMU cannot answer).
    Discard,
    /// Error, and the instance is unchanged (an illegal call or a refused request).
    Refused,
    /// Error, and the instance is in the error state afterwards (a call that failed).
    Fails,
}

impl Expect {
    /// Whether the status `status` is this answer.
    pub(super) fn accepts(self, status: i32) -> bool {
        match self {
            Expect::Ok => status == 0,
            Expect::OkOrWarning => status == 0 || status == 1,
            Expect::Discard => status == 2,
            Expect::Refused | Expect::Fails => status == 3,
        }
    }

    /// OK if `ok`, else refused.
    pub(super) fn ok_if(ok: bool) -> Expect {
        if ok { Expect::Ok } else { Expect::Refused }
    }
}

/// The model of one instance (everything an FMU state saves).
#[derive(Debug, Clone)]
pub(super) struct Sim {
    pub(super) st: St,
    /// The current communication point.
    pub(super) time: f64,
    pub(super) stop: Option<f64>,
    /// An engine exists (built by initialisation or by an output read in Initialization Mode).
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
    /// A fresh instance with the scenario and filter `specific` (else the generic defaults).
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
    /// filter) a filter that fits it; for the guided model, a scenario it can fly.
    pub(super) fn params_ok(&self, sc: &Scenarios, model: Model) -> bool {
        let Some(fits) = sc.fits.get(self.scenario.trim()) else {
            return false;
        };
        (!model.has_filter() || fits.contains(&self.filter.trim()))
            && (model != Model::Guided || sc.guided.iter().any(|g| g == self.scenario.trim()))
    }

    /// What setting up the experiment with `start` and `stop` (if defined) answers: FMI 2.0's
    /// fmi2SetupExperiment, FMI 3.0's fmi3EnterInitializationMode.
    pub(super) fn setup(&self, start: f64, stop: Option<f64>) -> Expect {
        Expect::ok_if(
            self.st == St::Instantiated
                && start == 0.0
                && stop.is_none_or(|t| t.is_finite() && t > 0.0),
        )
    }

    /// Whether a read of `vars` (already checked to resolve) needs the engine: an output scalar
    /// or an array.
    pub(super) fn needs_engine(vars: &[Variable], table: &[Var]) -> bool {
        vars.iter().any(|v| match v.what {
            What::Scalar(i) => table[i].causality == Causality::Output,
            What::Array(_) => true,
            What::Time | What::Slots => false,
        })
    }

    /// What a getter of type `ty` of `vars` answers once the arguments are valid (`None`
    /// entries: unknown references).
    pub(super) fn get(
        &self,
        sc: &Scenarios,
        model: Model,
        ty: Type3,
        vars: &[Option<Variable>],
        table: &[Var],
    ) -> Expect {
        if !self.st.readable() || vars.iter().any(|v| v.is_none_or(|v| v.ty != ty)) {
            return Expect::Refused;
        }
        let vars: Vec<Variable> = vars.iter().flatten().copied().collect();
        if Self::needs_engine(&vars, table) && !self.engine && !self.params_ok(sc, model) {
            return Expect::Refused;
        }
        Expect::Ok
    }

    /// Whether a setter of type `ty` of `v` may succeed (`valid`: the value passes the FMU's
    /// checks for this variable).
    pub(super) fn set_one(
        &self,
        v: Option<Variable>,
        ty: Type3,
        valid: bool,
        table: &[Var],
    ) -> bool {
        let Some(v) = v else {
            return false;
        };
        if v.ty != ty || !valid || !self.st.writable() {
            return false;
        }
        match v.what {
            What::Scalar(i) => match table[i].causality {
                Causality::Input => true,
                Causality::Parameter => matches!(self.st, St::Instantiated | St::Init),
                Causality::Output => false,
            },
            // Only its own value (checked by the caller through `valid`), and only until
            // initialisation ends (fixed variability, like the fixed parameters): this FMU has no
            // configuration mode.
            What::Slots => matches!(self.st, St::Instantiated | St::Init),
            What::Time | What::Array(_) => false,
        }
    }

    /// What a step from `t` of `h` answers, given the filter FMU's last processed epoch `nav`
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
            let too_many = !(substeps.is_finite() && substeps <= MAX_PREDICTION_SUBSTEPS as f64);
            if processed && (too_many || self.meas_time > duration * (1.0 + 1e-9)) {
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
