//! The FMI 3.0 side of the fuzzer ([`Fmi3`]): instances by `fmi3InstantiateCoSimulation`, the
//! experiment set up and Initialization Mode entered by `fmi3EnterInitializationMode`, and what
//! only FMI 3.0 has: the Int64 (Enumerations) and UInt64 (the structural parameter) values, the
//! arrays `est_x`, `est_sigma` and `est_covariance` against the scalar outputs and `nValues`
//! against their expanded length ([`arrays`]), the functions of capabilities the FMU does not
//! have and the types it has no variables of ([`unsupported`]), and instantiations it must
//! refuse ([`instantiate`]).

mod arrays;
mod instantiate;
mod unsupported;

use super::fuzzer::{Fuzzer, Saved, Version};
use super::model::{Expect, Sim, St};
use super::vals::Vals;
use super::variables::{Variable, fmi3_variables};

use anyhow::{Result, ensure};
use entrynav_fmi_host::{Api3, FmiInstance, Instantiate3, Slave3};
use entrynav_fmu::instance::Type3;
use entrynav_fmu::vars::ModelSpec;
use rand::RngExt;
use std::ffi::{CStr, CString};
use std::sync::Arc;

/// The fmi3 names a message may use besides the 75 functions.
const FMI3_TYPES: [&str; 11] = [
    "fmi3Instance",
    "fmi3FMUState",
    "fmi3OK",
    "fmi3Warning",
    "fmi3Discard",
    "fmi3Error",
    "fmi3Fatal",
    "fmi3True",
    "fmi3False",
    "fmi3ValueReference",
    "fmi3LogMessageCallback",
];

/// Start times (only 0 is accepted; -0 is 0) and stop times of fmi3EnterInitializationMode.
const STARTS: [f64; 6] = [0.0, 0.0, 0.0, -0.0, 1.0, f64::NAN];
const STOPS: [f64; 8] = [300.0, 1e9, 10.0, 1e-9, 0.0, f64::INFINITY, f64::NAN, -5.0];

/// An FMU through its fmi3 functions, with what its instantiations pass.
pub(super) struct Fmi3 {
    pub(super) api: Arc<Api3>,
    /// The instantiation token (the model's GUID).
    pub(super) token: CString,
    /// The resources folder, as the path fmi3InstantiateCoSimulation takes.
    pub(super) resources: CString,
}

impl Fmi3 {
    /// The FMI 3.0 view of `api`, whose library must report FMI 3.0, instantiated with `guid` and
    /// the resources folder `resources`.
    pub(super) fn load(api: Api3, guid: &str, resources: &std::path::Path) -> Result<Fmi3> {
        // SAFETY: returns a static C string.
        let version = unsafe { CStr::from_ptr((api.fmi3GetVersion)()) };
        ensure!(
            version.to_bytes() == b"3.0",
            "fmi3GetVersion answered {version:?}"
        );
        Ok(Fmi3 {
            api: Arc::new(api),
            token: CString::new(guid)?,
            resources: CString::new(resources.to_string_lossy().as_bytes())?,
        })
    }
}

impl Fuzzer<Fmi3> {
    /// fmi3EnterInitializationMode with a start time, a stop time or none and a tolerance or
    /// none: the experiment set-up of FMI 2.0 and the entry into Initialization Mode in one call.
    fn enter_init(&mut self, s: &Slave3, sim: &mut Sim) -> Result<()> {
        let start = STARTS[self.rng.random_range(0..STARTS.len())];
        let defined = self.rng.random_bool(0.6);
        let stop = STOPS[self.rng.random_range(0..STOPS.len())];
        let tolerance = [1e-6, 0.0, -1.0, f64::NAN][self.rng.random_range(0..4)];
        let tol_defined = self.rng.random_bool(0.5);
        let stop = defined.then_some(stop);
        let r = s.enter_initialization_mode(tol_defined.then_some(tolerance), start, stop);
        let e = sim.setup(start, stop);
        self.expect(
            s,
            &format!("fmi3EnterInitializationMode(start {start}, stop {stop:?})"),
            sim,
            e,
            r,
        )?;
        if e == Expect::Ok {
            (sim.st, sim.stop) = (St::Init, stop);
        }
        Ok(())
    }
}

impl Version for Fmi3 {
    type Instance = Slave3;
    const OTHER_PREFIX: &'static str = "fmi2";
    const TYPES: &'static [Type3] = &[
        Type3::Float64,
        Type3::Float64,
        Type3::Int32,
        Type3::Int64,
        Type3::UInt64,
        Type3::Boolean,
        Type3::String,
        Type3::Float64,
    ];
    const N_VALUES: bool = true;
    const SPECIAL_OPS: u32 = 8;

    fn variables(spec: &ModelSpec) -> Vec<Variable> {
        fmi3_variables(spec)
    }

    fn names() -> Vec<&'static str> {
        Api3::FUNCTIONS.iter().chain(&FMI3_TYPES).copied().collect()
    }

    fn instantiate(f: &mut Fuzzer<Self>, name: &str, logging_on: bool) -> Result<Slave3> {
        let name = CString::new(name)?;
        let args = Instantiate3 {
            logging_on,
            ..Instantiate3::new(
                Some(&name),
                Some(&f.version.token),
                Some(&f.version.resources),
            )
        };
        let s = Slave3::new(&f.version.api, &args);
        let msgs = s.take_messages();
        ensure!(
            !s.c.is_null(),
            "fmi3InstantiateCoSimulation refused a valid instantiation: {msgs:?}"
        );
        f.messages("fmi3InstantiateCoSimulation", &msgs)?;
        Ok(s)
    }

    fn null_instance(&self) -> Slave3 {
        Slave3::null(&self.api)
    }

    fn null_calls(s: &Slave3) -> Vec<i32> {
        let vr = 0u32;
        // SAFETY: a null instance must be refused unread.
        unsafe {
            vec![
                (s.api.fmi3EnterEventMode)(s.c),
                (s.api.fmi3GetFloat32)(s.c, &vr, 0, std::ptr::null_mut(), 0),
            ]
        }
    }

    fn initialise(f: &mut Fuzzer<Self>, s: &Slave3, sim: &mut Sim) -> Result<()> {
        f.enter_init(s, sim)
    }

    fn after_step(f: &mut Fuzzer<Self>, s: &Slave3, sim: &mut Sim) -> Result<()> {
        if f.slots > 0 && f.rng.random_bool(0.3) {
            f.check_arrays(s, sim)?;
        }
        Ok(())
    }

    fn special(
        f: &mut Fuzzer<Self>,
        k: u32,
        s: &Slave3,
        sim: &mut Sim,
        _: &mut Saved,
    ) -> Result<()> {
        match k {
            0 | 1 => f.unsupported(s, sim),
            2 => f.no_variables(s, sim),
            3 | 4 => f.check_arrays(s, sim),
            5 => f.get_nvalues(s, sim),
            6 => f.set_wide(s, sim),
            _ => f.instantiate_variants(),
        }
    }

    unsafe fn get_other(
        s: &Slave3,
        ty: Type3,
        (vrs, nvr): (*const u32, usize),
        room: usize,
        null_values: bool,
        n_values: usize,
    ) -> Option<(i32, Vals)> {
        macro_rules! call {
            ($f:ident, $v:ident) => {{
                let mut buf = vec![0; room];
                let p = if null_values {
                    std::ptr::null_mut()
                } else {
                    buf.as_mut_ptr()
                };
                // SAFETY: as the caller guarantees.
                let r = unsafe { (s.api.$f)(s.c, vrs, nvr, p, n_values) };
                (r, Vals::$v(buf))
            }};
        }
        match ty {
            Type3::Int64 => Some(call!(fmi3GetInt64, I64)),
            Type3::UInt64 => Some(call!(fmi3GetUInt64, U64)),
            _ => None,
        }
    }

    fn report(f: &Fuzzer<Self>, seconds: f64) -> String {
        let st = &f.stats;
        format!(
            "fuzz {} (FMI 3.0): {} calls in {} sequences ({seconds:.1} s), no crash; statuses OK {} / Warning {} / Discard {} / Error {} / Fatal {}; {} illegal or refused calls answered fmi3Error with the instance unchanged, {} failures moved it to the error state; {} steps done, {} refused for their work, {} huge and {} tiny steps, {} arguments over a bound; {} nValues mismatches, {} unknown or mistyped references, {} null arrays, {} calls of unsupported functions, {} instantiations refused, {} calls on freed or null instances; {} array reads checked against the scalars, {} FMU states serialised, deserialised and serialised again identically; {} log messages, none empty, in FMI 2.0 terms or disclosing a file",
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
            st.steps,
            st.work_refused,
            st.huge_steps,
            st.tiny_steps,
            st.over_bound,
            st.count_mismatches,
            st.bad_refs,
            st.null_arrays,
            st.unsupported,
            st.refused_instances,
            st.dead_calls,
            st.array_checks,
            st.round_trips,
            st.messages
        )
    }
}
