//! The FMI 2.0 side of the fuzzer ([`Fmi2`]): instances by `fmi2Instantiate`, the experiment
//! set up by `fmi2SetupExperiment` and Initialization Mode entered by its own call, and what
//! only FMI 2.0 has: the status queries (`fmi2Get*Status`, `fmi2LastSuccessfulTime` checked),
//! `fmi2CancelStep` and `fmi2GetDirectionalDerivative` (refused: no asynchronous steps, no
//! derivatives), and instantiations with another model's GUID or over-long arguments.

use super::fuzzer::{Fuzzer, Saved, Version};
use super::model::{Expect, Sim, St, same_time};
use super::vals::Vals;
use super::variables::{Variable, fmi2_variables};
use anyhow::{Result, ensure};
use entrynav_fmi_host::{Api, FmiInstance, HostError, Slave};
use entrynav_fmu::guid_of;
use entrynav_fmu::instance::Type3;
use entrynav_fmu::limits::MAX_STRING_BYTES;
use entrynav_fmu::vars::{Model, ModelSpec};
use rand::RngExt;
use std::ffi::c_int;
use std::sync::Arc;

/// The FMI 2.0 names a message may use besides the 34 functions.
const FMI2_TYPES: [&str; 21] = [
    "fmi2Component",
    "fmi2FMUstate",
    "fmi2OK",
    "fmi2Warning",
    "fmi2Discard",
    "fmi2Error",
    "fmi2Fatal",
    "fmi2Pending",
    "fmi2True",
    "fmi2False",
    "fmi2Real",
    "fmi2Integer",
    "fmi2Boolean",
    "fmi2String",
    "fmi2Status",
    "fmi2StatusKind",
    "fmi2DoStepStatus",
    "fmi2PendingStatus",
    "fmi2LastSuccessfulTime",
    "fmi2Terminated",
    "fmi2CallbackFunctions",
];

/// An FMU through its fmi2 functions, with what its instantiations pass.
pub(super) struct Fmi2 {
    pub(super) api: Arc<Api>,
    /// The model's GUID.
    pub(super) guid: String,
    /// The resources folder as a URI.
    pub(super) uri: String,
}

/// What fmi2Get*Status of `kind` through `function` answers (0 GetStatus, 1 GetRealStatus,
/// 2 GetIntegerStatus, 3 GetBooleanStatus, 4 GetStringStatus).
fn status_query(st: St, function: usize, kind: i32) -> Expect {
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

impl Fuzzer<Fmi2> {
    /// fmi2SetupExperiment with a start time (only 0 is accepted) and a stop time or none.
    fn setup_experiment(&mut self, s: &Slave, sim: &mut Sim) -> Result<()> {
        let start = [0.0, 0.0, 0.0, 1.0, f64::NAN][self.rng.random_range(0..5)];
        let defined = self.rng.random_bool(0.6);
        let stop =
            [300.0, 1e9, 10.0, 1e-9, f64::INFINITY, f64::NAN, -5.0][self.rng.random_range(0..7)];
        // SAFETY: our instance.
        let r = unsafe {
            (self.version.api.fmi2SetupExperiment)(s.c, 0, 0.0, start, defined as c_int, stop)
        };
        let e = sim.setup(start, defined.then_some(stop));
        self.expect(s, "fmi2SetupExperiment", sim, e, r)?;
        if e == Expect::Ok {
            sim.stop = defined.then_some(stop);
        }
        Ok(())
    }

    /// fmi2EnterInitializationMode (with or without the experiment set up before).
    fn enter_initialization(&mut self, s: &Slave, sim: &mut Sim) -> Result<()> {
        // SAFETY: our instance.
        let r = unsafe { (self.version.api.fmi2EnterInitializationMode)(s.c) };
        let legal = sim.st == St::Instantiated;
        self.expect(
            s,
            "fmi2EnterInitializationMode",
            sim,
            Expect::ok_if(legal),
            r,
        )?;
        if legal {
            sim.st = St::Init;
        }
        Ok(())
    }

    /// A status query (a random function and kind); fmi2LastSuccessfulTime is the model's time.
    fn status(&mut self, s: &Slave, sim: &mut Sim) -> Result<()> {
        let api = Arc::clone(&self.version.api);
        let function = self.rng.random_range(0..5usize);
        let kind = [-1, 0, 1, 2, 3, 4, 99][self.rng.random_range(0..7)];
        let e = status_query(sim.st, function, kind);
        let (mut st, mut x, mut i, mut b, mut p) =
            (0 as c_int, 0.0, 0 as c_int, 0 as c_int, std::ptr::null());
        // SAFETY: our instance and one value of the function's type.
        let r = unsafe {
            match function {
                0 => (api.fmi2GetStatus)(s.c, kind, &mut st),
                1 => (api.fmi2GetRealStatus)(s.c, kind, &mut x),
                2 => (api.fmi2GetIntegerStatus)(s.c, kind, &mut i),
                3 => (api.fmi2GetBooleanStatus)(s.c, kind, &mut b),
                _ => (api.fmi2GetStringStatus)(s.c, kind, &mut p),
            }
        };
        let what = format!("Get*Status #{function} kind {kind}");
        self.expect(s, &what, sim, e, r)?;
        if function == 1 && r == 0 {
            ensure!(
                same_time(x, sim.time),
                "fmi2LastSuccessfulTime {x}, expected {}",
                sim.time
            );
        }
        Ok(())
    }

    /// fmi2CancelStep or fmi2GetDirectionalDerivative: refused in every state.
    fn refused_always(&mut self, s: &Slave, sim: &mut Sim, cancel: bool) -> Result<()> {
        let (mut x, d, vr) = (0.0, 1.0, 0u32);
        // SAFETY: our instance; one element per array.
        let (r, what) = unsafe {
            match cancel {
                true => ((self.version.api.fmi2CancelStep)(s.c), "fmi2CancelStep"),
                false => (
                    (self.version.api.fmi2GetDirectionalDerivative)(
                        s.c, &vr, 1, &vr, 1, &d, &mut x,
                    ),
                    "fmi2GetDirectionalDerivative",
                ),
            }
        };
        self.expect(s, what, sim, Expect::Refused, r)
    }

    /// fmi2Instantiate with another model's GUID (refused by a bound library), an over-long
    /// GUID or name (refused), or the right GUID (accepted).
    fn instantiate_variants(&mut self) -> Result<()> {
        let other = Model::ALL
            .into_iter()
            .find(|m| m.identifier() != self.spec.identifier())
            .map(guid_of)
            .unwrap_or_default();
        let (name, guid, ok) = match self.rng.random_range(0..4) {
            0 => (
                "x".to_string(),
                other,
                !self.bound && self.spec.specific().is_none(),
            ),
            1 => ("x".to_string(), "{".repeat(300), false),
            2 => (
                "n".repeat(MAX_STRING_BYTES + 1),
                self.version.guid.clone(),
                false,
            ),
            _ => ("ok".to_string(), self.version.guid.clone(), true),
        };
        self.stats.calls += 1;
        match Slave::new(&self.version.api, &name, &guid, &self.version.uri) {
            Ok(_slave) => ensure!(ok, "fmi2Instantiate accepted {name:.20} / {guid:.60}"),
            Err(HostError::Instantiate(msgs)) => {
                ensure!(!ok, "fmi2Instantiate refused {guid}: {msgs:?}");
                ensure!(
                    msgs.iter().any(|m| m.status == 3 && !m.text.is_empty()),
                    "no reason logged"
                );
                self.messages("fmi2Instantiate", &msgs)?;
                self.stats.refused_instances += 1;
                if guid.len() > 256 || name.len() > MAX_STRING_BYTES {
                    self.stats.over_bound += 1;
                }
            }
            Err(e) => return Err(e.into()),
        }
        Ok(())
    }
}

impl Version for Fmi2 {
    type Instance = Slave;
    const OTHER_PREFIX: &'static str = "fmi3";
    const TYPES: &'static [Type3] = &[
        Type3::Float64,
        Type3::Float64,
        Type3::Int32,
        Type3::Boolean,
        Type3::String,
    ];
    const N_VALUES: bool = false;
    const SPECIAL_OPS: u32 = 5;

    fn variables(spec: &ModelSpec) -> Vec<Variable> {
        fmi2_variables(spec)
    }

    fn names() -> Vec<&'static str> {
        Api::FUNCTIONS.iter().chain(&FMI2_TYPES).copied().collect()
    }

    fn instantiate(f: &mut Fuzzer<Self>, name: &str, logging_on: bool) -> Result<Slave> {
        let s = Slave::instantiate(
            &f.version.api,
            name,
            &f.version.guid,
            &f.version.uri,
            logging_on,
        )?;
        let msgs = s.take_messages();
        f.messages("fmi2Instantiate", &msgs)?;
        Ok(s)
    }

    fn null_instance(&self) -> Slave {
        Slave::null(&self.api)
    }

    fn null_calls(s: &Slave) -> Vec<i32> {
        // SAFETY: a null instance must be refused unread.
        unsafe { vec![(s.api.fmi2CancelStep)(s.c)] }
    }

    fn initialise(f: &mut Fuzzer<Self>, s: &Slave, sim: &mut Sim) -> Result<()> {
        match f.rng.random_bool(0.5) {
            true => f.setup_experiment(s, sim),
            false => f.enter_initialization(s, sim),
        }
    }

    fn after_step(_: &mut Fuzzer<Self>, _: &Slave, _: &mut Sim) -> Result<()> {
        Ok(())
    }

    fn special(
        f: &mut Fuzzer<Self>,
        k: u32,
        s: &Slave,
        sim: &mut Sim,
        _: &mut Saved,
    ) -> Result<()> {
        match k {
            0 | 1 => f.status(s, sim),
            2 => f.refused_always(s, sim, true),
            3 => f.refused_always(s, sim, false),
            _ => f.instantiate_variants(),
        }
    }

    unsafe fn get_other(
        _: &Slave,
        _: Type3,
        _: (*const u32, usize),
        _: usize,
        _: bool,
        _: usize,
    ) -> Option<(i32, Vals)> {
        None
    }

    fn report(f: &Fuzzer<Self>, seconds: f64) -> String {
        let st = &f.stats;
        format!(
            "fuzz {}: {} calls in {} sequences ({seconds:.1} s), no crash; statuses OK {} / Warning {} / Discard {} / Error {} / Fatal {}; {} illegal or refused calls answered fmi2Error with the instance unchanged, {} failures moved it to the error state; {} steps refused for their work, {} huge and {} tiny steps, {} arguments over a bound; {} steps done, {} unknown or mistyped references, {} null arrays, {} instantiations refused, {} calls on freed or null instances, {} FMU states serialised, deserialised and serialised again identically; {} log messages, none empty or disclosing a file",
            f.spec.identifier(),
            st.calls,
            st.sequences,
            st.statuses[0],
            st.statuses[1],
            st.statuses[2],
            st.statuses[3],
            st.statuses[4],
            st.refused,
            st.failed,
            st.work_refused,
            st.huge_steps,
            st.tiny_steps,
            st.over_bound,
            st.steps,
            st.bad_refs,
            st.null_arrays,
            st.refused_instances,
            st.dead_calls,
            st.round_trips,
            st.messages
        )
    }
}
