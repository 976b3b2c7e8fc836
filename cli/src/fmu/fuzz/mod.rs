//! `entrynav fmu fuzz`: random FMI call sequences through our host against a model of the
//! co-simulation state machine ([`model`]). Every call is checked: an illegal call or a refused
//! request must be answered with fmi2Error and leave the instance as it was, a legal call must
//! succeed, a failing one must put the instance in the error state, every log message must be
//! non-empty and none may disclose a host file. The values cover huge and tiny intervals and
//! step sizes, and every size-like argument below and above its bound (value-reference counts,
//! string lengths, category counts, serialized-state sizes, numbers of FMU states, measurement
//! times). CI runs 100,000 calls per FMU; `--calls 5000000` is the long mode. An FMI 3.0 FMU
//! (`<id>-fmi3.fmu`) is fuzzed through its fmi3 functions instead ([`super::fuzz3`]).

#![allow(non_snake_case)]

mod calls;
pub(super) mod model;
mod ops;
mod values;

use super::*;
use entrynav_fmi_host::*;
use model::{Expect, Scenarios, Sim};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;

/// Arguments of `entrynav fmu fuzz`.
#[derive(Args)]
pub(super) struct FuzzArgs {
    /// The .fmu file.
    file: PathBuf,
    /// FMI calls in all (fmi2, or fmi3 for an FMI 3.0 FMU; CI: 100,000 per FMU; the long mode:
    /// 5,000,000).
    #[arg(long, default_value_t = 100_000)]
    calls: usize,
    /// Longest call sequence on one instance.
    #[arg(long, default_value_t = 80)]
    max_sequence: usize,
    /// Seed of the random sequences.
    #[arg(long, default_value_t = 1)]
    seed: u64,
}

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
    huge_steps: usize,
    tiny_steps: usize,
    over_bound: usize,
    messages: usize,
}

/// The fuzzer: the unpacked FMU, its table, the scenario facts the model needs, and buffers
/// for the over-the-bound calls.
pub(super) struct Fuzzer<'a> {
    u: &'a Unpacked,
    vars: Vec<Var>,
    guid: String,
    uri: String,
    rng: ChaCha8Rng,
    sc: Scenarios,
    /// A real buffer longer than one call may pass (MAX_VALUE_REFS + 1 elements).
    big_vr: Vec<u32>,
    big_out: Vec<f64>,
    stats: Stats,
}

impl Fuzzer<'_> {
    /// Check a call's status against `expect` and the messages it logged.
    fn expect(
        &mut self,
        s: &Slave,
        op: &str,
        sim: &Sim,
        expect: Expect,
        status: i32,
        seen: usize,
    ) -> Result<()> {
        self.stats.calls += 1;
        self.stats.statuses[status.clamp(0, 4) as usize] += 1;
        let msgs = s.messages();
        ensure!(
            expect.accepts(status),
            "{op} in state {:?} (t = {}) answered {status}, expected {expect:?}; log: {:?}",
            sim.st,
            sim.time,
            &msgs[seen.min(msgs.len())..]
        );
        for (_, m) in &msgs[seen.min(msgs.len())..] {
            ensure!(!m.trim().is_empty(), "{op}: an empty log message");
            ensure!(
                !m.contains("root:x:"),
                "{op}: a log message discloses a host file: {m}"
            );
            self.stats.messages += 1;
        }
        match expect {
            Expect::Refused => self.stats.refused += 1,
            Expect::Fails => self.stats.failed += 1,
            _ => {}
        }
        Ok(())
    }

    /// One random call sequence on a fresh instance.
    fn sequence(&mut self, len: usize) -> Result<()> {
        let name = format!("fuzz{}", self.stats.sequences);
        let s = Slave::new(self.u, &name, &self.guid, &self.uri)?;
        self.stats.calls += 1;
        self.stats.sequences += 1;
        let mut sim = Sim::new(model::start_params(&self.u.spec));
        let mut saved: Vec<(*mut std::ffi::c_void, Sim)> = Vec::new();
        for _ in 0..len {
            self.op(&s, &mut sim, &mut saved)?;
        }
        for (mut p, _) in saved {
            // SAFETY: our instance and a state it handed out.
            unsafe { (self.u.api.fmi2FreeFMUstate)(s.c, &mut p) };
        }
        Ok(())
    }
}

pub(super) fn fuzz(a: &FuzzArgs) -> Result<()> {
    let u = unpack(&a.file)?;
    ensure!(
        u.model != Model::Guidance,
        "fmu fuzz has no model of MarsEntryGuidance's statuses yet (its refusals depend on the estimate it is given); fuzz MarsEntryNav, MarsEntryNavFilter or MarsEntryTruth"
    );
    if u.fmi_version == 3 {
        return super::fuzz3::fuzz3(&u, a.calls, a.max_sequence, a.seed);
    }
    let mut f = Fuzzer {
        vars: u.spec.vars().to_vec(),
        guid: u.spec.guid().to_string(),
        uri: file_uri(&u.dir.join("resources")),
        rng: ChaCha8Rng::seed_from_u64(a.seed),
        sc: Scenarios::new(u.spec.specific())?,
        big_vr: vec![0; entrynav_fmu::limits::MAX_VALUE_REFS + 1],
        big_out: vec![0.0; entrynav_fmu::limits::MAX_VALUE_REFS + 1],
        stats: Stats::default(),
        u: &u,
    };
    let clock = Instant::now();
    while f.stats.calls < a.calls {
        let len = f.rng.random_range(1..=a.max_sequence.max(1));
        f.sequence(len)?;
    }
    f.null_and_freed()?;
    let st = &f.stats;
    println!(
        "fuzz {}: {} calls in {} sequences ({:.1} s), no crash; statuses OK {} / Warning {} / Discard {} / Error {} / Fatal {}; {} illegal or refused calls answered fmi2Error with the instance unchanged, {} failures moved it to the error state; {} steps refused for their work, {} huge and {} tiny steps, {} arguments over a bound; {} log messages, none empty or disclosing a file",
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
        st.work_refused,
        st.huge_steps,
        st.tiny_steps,
        st.over_bound,
        st.messages
    );
    ensure!(st.statuses[4] == 0, "an fmi2Fatal");
    Ok(())
}

impl Fuzzer<'_> {
    /// Null and freed instances are refused by every function.
    fn null_and_freed(&mut self) -> Result<()> {
        let api = &self.u.api;
        // SAFETY: null is allowed everywhere.
        unsafe {
            (api.fmi2FreeInstance)(std::ptr::null_mut());
            ensure!((api.fmi2DoStep)(std::ptr::null_mut(), 0.0, 1.0, 0) == 3);
            ensure!((api.fmi2Terminate)(std::ptr::null_mut()) == 3);
            ensure!((api.fmi2Reset)(std::ptr::null_mut()) == 3);
        }
        self.stats.calls += 4;
        Ok(())
    }
}
