//! The FMI 3.0 fuzzer's model of an instance: the co-simulation state machine without event mode
//! (*Instantiated*, *Initialization Mode*, *Step Mode*, *Terminated*, the error state) as the FMU
//! implements it, the variables as FMI 3.0 types them ([`V3`]), and what every call must answer.

use super::super::*;
use entrynav_fmu::instance::Type3;
use entrynav_fmu::limits::MAX_PREDICTION_SUBSTEPS;
use entrynav_fmu::vars::fmi3::{Extra, extras, state_slots};
use entrynav_fmu::vars::{DEFAULT_FILTER, DEFAULT_SCENARIO, DEFAULT_SEED, ModelSpec};

/// The states of the FMI 3.0 co-simulation state machine this FMU has.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum St {
    Instantiated,
    Init,
    Step,
    Terminated,
    Error,
}

impl St {
    /// Where fmi3Get{VariableType} is allowed.
    pub(super) fn readable(self) -> bool {
        matches!(self, St::Init | St::Step | St::Terminated | St::Error)
    }

    /// Where fmi3Set{VariableType} is allowed.
    pub(super) fn writable(self) -> bool {
        matches!(self, St::Instantiated | St::Init | St::Step)
    }
}

/// What a call must answer.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Expect {
    /// fmi3OK.
    Ok,
    /// fmi3OK or fmi3Warning.
    OkOrWarning,
    /// fmi3Error, and the instance is unchanged (an illegal call or a refused request).
    Refused,
    /// fmi3Error, and the instance is in the error state afterwards (a call that failed).
    Fails,
}

impl Expect {
    pub(super) fn accepts(self, status: i32) -> bool {
        match self {
            Expect::Ok => status == 0,
            Expect::OkOrWarning => status == 0 || status == 1,
            Expect::Refused | Expect::Fails => status == 3,
        }
    }

    pub(super) fn ok_if(ok: bool) -> Expect {
        if ok { Expect::Ok } else { Expect::Refused }
    }
}

/// What an FMI 3.0 variable is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum What {
    /// A scalar of the shared table (its index = value reference).
    Scalar(usize),
    /// `time`, the independent variable.
    Time,
    /// `n_state_slots`, the structural parameter.
    Slots,
    /// `est_x`, `est_sigma` or `est_covariance`.
    Array(Extra),
}

/// A variable of the FMI 3.0 description.
#[derive(Debug, Clone, Copy)]
pub(super) struct V3 {
    pub(super) vr: u32,
    pub(super) ty: Type3,
    pub(super) what: What,
    /// The number of values it holds.
    pub(super) len: usize,
}

/// Every variable of `spec` as the FMI 3.0 description has it: the scalars with their FMI 2.0
/// value references (an Enumeration as Int64), then `time`, `n_state_slots` and the arrays.
pub(super) fn variables(spec: &ModelSpec) -> Vec<V3> {
    let slots = state_slots(spec);
    let mut out: Vec<V3> = spec
        .vars()
        .iter()
        .enumerate()
        .map(|(i, v)| V3 {
            vr: v.vr,
            ty: match v.ty {
                Type::Real => Type3::Float64,
                Type::Integer if v.declared.is_some() => Type3::Int64,
                Type::Integer => Type3::Int32,
                Type::Boolean => Type3::Boolean,
                Type::String => Type3::String,
            },
            what: What::Scalar(i),
            len: 1,
        })
        .collect();
    for x in extras(spec) {
        let (ty, what) = match x.extra {
            Extra::Time => (Type3::Float64, What::Time),
            Extra::Slots => (Type3::UInt64, What::Slots),
            e => (Type3::Float64, What::Array(e)),
        };
        out.push(V3 {
            vr: x.vr,
            ty,
            what,
            len: x.len(slots),
        });
    }
    out
}

pub(super) use super::super::fuzz::model::Scenarios;

/// The model of one instance (everything fmi3GetFMUState saves).
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

    /// What fmi3EnterInitializationMode(start, stop if defined) answers.
    pub(super) fn enter_init(&self, start: f64, stop: Option<f64>) -> Expect {
        Expect::ok_if(
            self.st == St::Instantiated
                && start == 0.0
                && stop.is_none_or(|t| t.is_finite() && t > 0.0),
        )
    }

    /// Whether a read of `vars` (already checked to resolve) needs the engine: an output scalar
    /// or an array.
    pub(super) fn needs_engine(vars: &[V3], table: &[Var]) -> bool {
        vars.iter().any(|v| match v.what {
            What::Scalar(i) => table[i].causality == Causality::Output,
            What::Array(_) => true,
            What::Time | What::Slots => false,
        })
    }

    /// What an fmi3Get of `vars` answers once the arguments are valid (`None` entries: unknown
    /// references).
    pub(super) fn get(
        &self,
        sc: &Scenarios,
        model: Model,
        ty: Type3,
        vars: &[Option<V3>],
        table: &[Var],
    ) -> Expect {
        if !self.st.readable() || vars.iter().any(|v| v.is_none_or(|v| v.ty != ty)) {
            return Expect::Refused;
        }
        let vars: Vec<V3> = vars.iter().flatten().copied().collect();
        if Self::needs_engine(&vars, table) && !self.engine && !self.params_ok(sc, model) {
            return Expect::Refused;
        }
        Expect::Ok
    }

    /// Whether an fmi3Set of `v` (of type `ty`) to a value may succeed (`valid`: the value passes
    /// the FMU's checks for this variable).
    pub(super) fn set_one(&self, v: Option<V3>, ty: Type3, valid: bool, table: &[Var]) -> bool {
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

    /// What fmi3DoStep(t, h) answers, given the filter FMU's last processed epoch `nav`
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
