//! `entrynav fmu fuzz` of an FMI 3.0 FMU (`<Model>-fmi3.fmu`, chosen by the description's
//! `fmiVersion`): random fmi3 call sequences on instances made by fmi3InstantiateCoSimulation,
//! through the host's [`Api3`], against a model of the co-simulation state machine without event
//! mode ([`model`]). As for FMI 2.0 ([`super::fuzz`]), every call is checked: an illegal call or a
//! refused request must be answered with fmi3Error, a logged reason, and the instance as it was;
//! a legal call must succeed; a failing one must put the instance in the error state. FMI 3.0
//! adds what this fuzzer covers besides: the FMI 3.0 types (Float64, Int32, Enumerations as Int64,
//! the structural parameter as UInt64, Boolean as a byte, String), `nValues` against the expanded
//! length of the arrays `est_x`, `est_sigma` and `est_covariance`, the arrays' agreement with the
//! scalar outputs, `lastSuccessfulTime` and the flags of fmi3DoStep, every function of a
//! capability the FMU does not have (fmi3Error, or NULL for the other instantiation functions),
//! and instantiations it must refuse (event mode, intermediate variables, bad names and tokens).
//! Every log message must be non-empty, in FMI 3.0 terms (no `fmi2`, only fmi3 names that exist)
//! and disclose no host file.

#![allow(non_snake_case)]

mod calls;
mod inst;
mod model;
mod ops;
mod setters;
mod state;
mod values;

use super::*;
use entrynav_fmi_host::{Api3, Message3, State3, Unpacked};
use entrynav_fmu::vars::fmi3::state_slots;
use inst::Inst;
use model::{Expect, Scenarios, Sim, V3};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::HashSet;
use std::ffi::CString;

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

/// What the fuzzer did.
#[derive(Debug, Default)]
pub(super) struct Stats {
    calls: usize,
    sequences: usize,
    statuses: [usize; 5],
    refused: usize,
    failed: usize,
    /// Steps refused because their work would be over a bound (the filter FMU's prediction).
    work_refused: usize,
    /// Steps that succeeded.
    steps: usize,
    huge_steps: usize,
    tiny_steps: usize,
    over_bound: usize,
    /// Calls whose `nValues` did not match what the references hold.
    count_mismatches: usize,
    /// Calls naming an unknown value reference or one of another type.
    bad_refs: usize,
    /// Calls with a null array and a non-zero count.
    null_arrays: usize,
    /// Calls of functions of capabilities the FMU does not have.
    unsupported: usize,
    /// Instantiations the FMU had to refuse (NULL).
    refused_instances: usize,
    /// Array reads compared with the scalar outputs.
    array_checks: usize,
    /// Serialised FMU states deserialised and serialised again byte for byte.
    round_trips: usize,
    /// Calls on freed or null instances.
    dead_calls: usize,
    messages: usize,
}

/// The fuzzer: the unpacked FMU, its fmi3 functions and variables, the scenario facts the model
/// needs, and buffers for the over-the-bound calls.
pub(super) struct Fuzzer<'a> {
    u: &'a Unpacked,
    api: &'a Api3,
    /// The scalar table.
    vars: Vec<Var>,
    /// Every variable of the FMI 3.0 description; index = value reference.
    v3: Vec<V3>,
    /// `n_state_slots`.
    slots: usize,
    token: CString,
    /// The resources folder, as the path fmi3InstantiateCoSimulation takes.
    resources: CString,
    rng: ChaCha8Rng,
    sc: Scenarios,
    /// References and values longer than one call may pass (MAX_VALUE_REFS + 1 elements).
    big_vr: Vec<u32>,
    big_out: Vec<f64>,
    /// The fmi3 names a message may contain.
    names: HashSet<&'static str>,
    stats: Stats,
}

impl Fuzzer<'_> {
    /// Check a call's status against `expect`, and the messages it logged.
    fn expect(&mut self, s: &Inst, op: &str, sim: &Sim, expect: Expect, status: i32) -> Result<()> {
        self.stats.calls += 1;
        self.stats.statuses[status.clamp(0, 4) as usize] += 1;
        let msgs = s.take();
        ensure!(
            expect.accepts(status),
            "{op} in state {:?} (t = {}) answered {status}, expected {expect:?}; log: {msgs:?}",
            sim.st,
            sim.time
        );
        self.messages(op, &msgs)?;
        ensure!(
            status != 3 || msgs.iter().any(|m| m.0 == 3),
            "{op} answered fmi3Error without logging a reason"
        );
        ensure!(
            status >= 3 || msgs.iter().all(|m| m.0 < 3),
            "{op} answered {status} but logged an error: {msgs:?}"
        );
        match expect {
            Expect::Refused => self.stats.refused += 1,
            Expect::Fails => self.stats.failed += 1,
            _ => {}
        }
        Ok(())
    }

    /// Every message non-empty, with a category, in FMI 3.0 terms (no `fmi2`; every fmi3 name it
    /// uses exists) and disclosing no host file.
    fn messages(&mut self, op: &str, msgs: &[Message3]) -> Result<()> {
        for (status, category, m) in msgs {
            ensure!(!m.trim().is_empty(), "{op}: an empty log message");
            ensure!(
                (0..=4).contains(status) && !category.trim().is_empty(),
                "{op}: status {status}, category '{category}': {m}"
            );
            ensure!(
                !m.to_ascii_lowercase().contains("fmi2"),
                "{op}: a log message in FMI 2.0 terms: {m}"
            );
            ensure!(
                !m.contains("root:x:"),
                "{op}: a log message discloses a host file: {m}"
            );
            for (i, _) in m.match_indices("fmi3") {
                let name: String = m[i..]
                    .chars()
                    .take_while(char::is_ascii_alphanumeric)
                    .collect();
                ensure!(
                    self.names.contains(name.as_str()),
                    "{op}: a log message names {name}, which is no FMI 3.0 function or type: {m}"
                );
            }
            self.stats.messages += 1;
        }
        Ok(())
    }

    /// One random call sequence on a fresh instance, then its states and the instance freed.
    fn sequence(&mut self, len: usize) -> Result<()> {
        let name = CString::new(format!("fuzz{}", self.stats.sequences))?;
        let logging_on = self.rng.random_bool(0.5);
        let s = Inst::cosim(
            self.api,
            &inst::Args {
                logging_on,
                ..inst::Args::new(Some(&name), Some(&self.token), Some(&self.resources))
            },
        );
        self.stats.calls += 1;
        self.stats.sequences += 1;
        let msgs = s.take();
        ensure!(
            !s.c.is_null(),
            "fmi3InstantiateCoSimulation refused a valid instantiation: {msgs:?}"
        );
        self.messages("fmi3InstantiateCoSimulation", &msgs)?;
        let mut sim = Sim::new(self.specific());
        let mut saved: Vec<(State3, Sim)> = Vec::new();
        for _ in 0..len {
            self.op(&s, &mut sim, &mut saved)?;
        }
        // Free the states, or leave them to fmi3FreeInstance.
        if self.rng.random_bool(0.5) {
            for (mut p, _) in saved {
                // SAFETY: our instance and a state it handed out.
                let r = unsafe { (self.api.fmi3FreeFMUState)(s.c, &mut p) };
                self.expect(&s, "fmi3FreeFMUState", &sim, Expect::Ok, r)?;
            }
        }
        self.free(s)
    }

    /// fmi3FreeInstance, then (sometimes) calls on the freed instance: refused, nothing logged.
    fn free(&mut self, mut s: Inst) -> Result<()> {
        s.free();
        self.stats.calls += 1;
        if self.rng.random_bool(0.2) {
            let mut last = f64::NAN;
            let (mut a, mut b, mut c) = (7u8, 7u8, 7u8);
            // SAFETY: a freed token must be refused without being used.
            let r = unsafe {
                [
                    (self.api.fmi3DoStep)(s.c, 0.0, 1.0, 0, &mut a, &mut b, &mut c, &mut last),
                    (self.api.fmi3Reset)(s.c),
                    (self.api.fmi3ExitInitializationMode)(s.c),
                ]
            };
            // SAFETY: freeing a freed instance is a no-op.
            unsafe { (self.api.fmi3FreeInstance)(s.c) };
            self.stats.calls += 4;
            self.stats.dead_calls += 4;
            self.stats.statuses[3] += 3;
            ensure!(r == [3, 3, 3], "calls on a freed instance answered {r:?}");
            ensure!(
                (a, b, c) == (7, 7, 7) && last.is_nan(),
                "fmi3DoStep on a freed instance wrote its outputs"
            );
            let msgs = s.take();
            ensure!(
                msgs.is_empty(),
                "a freed instance logged through its callback: {msgs:?}"
            );
        }
        Ok(())
    }

    /// The scenario and filter of a specific FMU.
    fn specific(&self) -> Option<(&str, &str)> {
        crate::fmu::fuzz::model::start_params(&self.u.spec)
    }

    /// Null instances are refused by every function (and freed without harm).
    fn null_instance(&mut self) -> Result<()> {
        let api = self.api;
        let null = std::ptr::null_mut();
        let (vr, mut x, mut p) = (0u32, 0.0, std::ptr::null_mut());
        // SAFETY: null must be refused everywhere without being used.
        let r = unsafe {
            (api.fmi3FreeInstance)(null);
            [
                (api.fmi3DoStep)(
                    null,
                    0.0,
                    1.0,
                    0,
                    null.cast(),
                    null.cast(),
                    null.cast(),
                    &mut x,
                ),
                (api.fmi3Terminate)(null),
                (api.fmi3Reset)(null),
                (api.fmi3EnterInitializationMode)(null, 0, 0.0, 0.0, 0, 0.0),
                (api.fmi3GetFloat64)(null, &vr, 1, &mut x, 1),
                (api.fmi3SetDebugLogging)(null, 1, 0, std::ptr::null()),
                (api.fmi3GetFMUState)(null, &mut p),
                (api.fmi3EnterEventMode)(null),
                (api.fmi3GetFloat32)(null, &vr, 0, std::ptr::null_mut(), 0),
            ]
        };
        self.stats.calls += 10;
        self.stats.dead_calls += 10;
        self.stats.statuses[3] += r.len();
        ensure!(
            r.iter().all(|&s| s == 3),
            "a null instance was answered {r:?}"
        );
        ensure!(
            p.is_null(),
            "fmi3GetFMUState of a null instance wrote a state"
        );
        Ok(())
    }
}

/// Run `calls` fmi3 calls (at least) on the FMI 3.0 FMU `u`, sequences of at most
/// `max_sequence` calls, from `seed`; print the statistics.
pub(super) fn fuzz3(u: &Unpacked, calls: usize, max_sequence: usize, seed: u64) -> Result<()> {
    let api = Api3::load(&u.library)?;
    // SAFETY: returns a static C string.
    let version = unsafe { CStr::from_ptr((api.fmi3GetVersion)()) };
    ensure!(
        version.to_bytes() == b"3.0",
        "fmi3GetVersion answered {version:?}"
    );
    let resources = u.dir.join("resources");
    let mut f = Fuzzer {
        u,
        api: &api,
        vars: u.spec.vars().to_vec(),
        v3: model::variables(&u.spec),
        slots: state_slots(&u.spec),
        token: CString::new(u.spec.guid())?,
        resources: CString::new(resources.to_string_lossy().as_bytes())?,
        rng: ChaCha8Rng::seed_from_u64(seed),
        sc: Scenarios::new(u.spec.specific())?,
        big_vr: vec![0; entrynav_fmu::limits::MAX_VALUE_REFS + 1],
        big_out: vec![0.0; entrynav_fmu::limits::MAX_VALUE_REFS + 1],
        names: Api3::FUNCTIONS.iter().chain(&FMI3_TYPES).copied().collect(),
        stats: Stats::default(),
    };
    ensure!(
        f.v3.iter().enumerate().all(|(i, v)| v.vr as usize == i),
        "the FMI 3.0 value references are not 0, 1, 2, …"
    );
    let clock = Instant::now();
    while f.stats.calls < calls {
        let len = f.rng.random_range(1..=max_sequence.max(1));
        f.sequence(len)?;
    }
    f.null_instance()?;
    let st = &f.stats;
    println!(
        "fuzz {} (FMI 3.0): {} calls in {} sequences ({:.1} s), no crash; statuses OK {} / Warning {} / Discard {} / Error {} / Fatal {}; {} illegal or refused calls answered fmi3Error with the instance unchanged, {} failures moved it to the error state; {} steps done, {} refused for their work, {} huge and {} tiny steps, {} arguments over a bound; {} nValues mismatches, {} unknown or mistyped references, {} null arrays, {} calls of unsupported functions, {} instantiations refused, {} calls on freed or null instances; {} array reads checked against the scalars, {} FMU states serialised, deserialised and serialised again identically; {} log messages, none empty, in FMI 2.0 terms or disclosing a file",
        u.spec.identifier(),
        st.calls,
        st.sequences,
        clock.elapsed().as_secs_f64(),
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
    );
    ensure!(st.statuses[4] == 0, "an fmi3Fatal");
    Ok(())
}
