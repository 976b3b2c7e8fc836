//! [`Fuzzer`]: one FMU under test through one FMI version, its random number generator and the
//! facts the model needs; the check of every answer ([`Fuzzer::expect`], [`Fuzzer::messages`]),
//! a random call sequence on a fresh instance, and the calls on freed and null instances.

use super::model::{Expect, Sim};
use super::scenarios::Scenarios;
use super::stats::Stats;
use super::variables::{Variable, What};
use super::version::Version;
use crate::fmu::defaults::start_params;
use anyhow::{Result, ensure};
use entrynav_fmi_host::{FmiInstance, FmuState, Message};
use entrynav_fmu::instance::Type3;
use entrynav_fmu::limits::MAX_VALUE_REFS;
use entrynav_fmu::vars::fmi3::state_slots;
use entrynav_fmu::vars::{Key, Model, ModelSpec, Var};
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::collections::HashSet;
use std::sync::Arc;

/// The FMU states a sequence holds, each with the model it saved.
pub(super) type Saved = Vec<(FmuState, Sim)>;

/// The FMU under test through the version `V`.
pub(super) struct Fuzzer<V: Version> {
    /// The version: its functions and what an instantiation passes.
    pub(super) version: V,
    pub(super) spec: Arc<ModelSpec>,
    pub(super) model: Model,
    /// The library is bound to its model (a packed FMU; `false`: a development library).
    pub(super) bound: bool,
    /// The scalar table.
    pub(super) vars: Vec<Var>,
    /// Every variable of the version's description; index = value reference.
    pub(super) variables: Vec<Variable>,
    /// `n_state_slots` (the arrays' dimension).
    pub(super) slots: usize,
    pub(super) rng: ChaCha8Rng,
    pub(super) sc: Scenarios,
    /// References and values longer than one call may pass (MAX_VALUE_REFS + 1 elements).
    pub(super) big_vr: Vec<u32>,
    pub(super) big_out: Vec<f64>,
    /// The names of the version a message may contain.
    names: HashSet<&'static str>,
    pub(super) stats: Stats,
}

impl<V: Version> Fuzzer<V> {
    /// The fuzzer of `spec` through `version` (`bound`: the library is bound to its model), from
    /// `seed`.
    pub(super) fn new(
        version: V,
        spec: Arc<ModelSpec>,
        bound: bool,
        seed: u64,
    ) -> Result<Fuzzer<V>> {
        let variables = V::variables(&spec);
        ensure!(
            variables
                .iter()
                .enumerate()
                .all(|(i, v)| v.vr as usize == i),
            "the value references are not 0, 1, 2, …"
        );
        Ok(Fuzzer {
            version,
            model: spec.model(),
            bound,
            vars: spec.vars().to_vec(),
            variables,
            slots: state_slots(&spec),
            rng: ChaCha8Rng::seed_from_u64(seed),
            sc: Scenarios::new(spec.specific())?,
            big_vr: vec![0; MAX_VALUE_REFS + 1],
            big_out: vec![0.0; MAX_VALUE_REFS + 1],
            names: V::names().into_iter().collect(),
            stats: Stats::default(),
            spec,
        })
    }

    /// A fresh instance's model.
    pub(super) fn fresh(&self) -> Sim {
        Sim::new(start_params(&self.spec))
    }

    /// Check a call's status against `expect`, and the messages it logged: an error comes with a
    /// logged reason, anything else with no error logged.
    pub(super) fn expect(
        &mut self,
        s: &V::Instance,
        op: &str,
        sim: &Sim,
        expect: Expect,
        status: i32,
    ) -> Result<()> {
        self.stats.calls += 1;
        self.stats.statuses[status.clamp(0, 4) as usize] += 1;
        let msgs = s.take_messages();
        ensure!(
            expect.accepts(status),
            "{op} in state {:?} (t = {}) answered {status}, expected {expect:?}; log: {msgs:?}",
            sim.st,
            sim.time
        );
        self.messages(op, &msgs)?;
        ensure!(
            status != 3 || msgs.iter().any(|m| m.status == 3),
            "{op} answered {}Error without logging a reason",
            <V::Instance as FmiInstance>::PREFIX
        );
        ensure!(
            status >= 3 || msgs.iter().all(|m| m.status < 3),
            "{op} answered {status} but logged an error: {msgs:?}"
        );
        match expect {
            Expect::Refused => self.stats.refused += 1,
            Expect::Fails => self.stats.failed += 1,
            _ => {}
        }
        Ok(())
    }

    /// Every message non-empty, with a status and a category, in the version's terms (no name
    /// of the other version; every name of this one it uses exists) and disclosing no host file.
    pub(super) fn messages(&mut self, op: &str, msgs: &[Message]) -> Result<()> {
        let prefix = <V::Instance as FmiInstance>::PREFIX;
        for Message {
            status,
            category,
            text: m,
        } in msgs
        {
            ensure!(!m.trim().is_empty(), "{op}: an empty log message");
            ensure!(
                (0..=4).contains(status) && !category.trim().is_empty(),
                "{op}: status {status}, category '{category}': {m}"
            );
            ensure!(
                !m.to_ascii_lowercase().contains(V::OTHER_PREFIX),
                "{op}: a log message in the terms of another FMI version: {m}"
            );
            ensure!(
                !m.contains("root:x:"),
                "{op}: a log message discloses a host file: {m}"
            );
            for (i, _) in m.match_indices(prefix) {
                let name: String = m[i..]
                    .chars()
                    .take_while(char::is_ascii_alphanumeric)
                    .collect();
                ensure!(
                    self.names.contains(name.as_str()),
                    "{op}: a log message names {name}, which is no {prefix} function or type: {m}"
                );
            }
            self.stats.messages += 1;
        }
        Ok(())
    }

    /// One random call sequence of `len` calls on a fresh instance, then its states freed (or
    /// left to the instance's free) and the instance freed.
    pub(super) fn sequence(&mut self, len: usize) -> Result<()> {
        let name = format!("fuzz{}", self.stats.sequences);
        let logging_on = self.rng.random_bool(0.5);
        let s = V::instantiate(self, &name, logging_on)?;
        self.stats.calls += 1;
        self.stats.sequences += 1;
        let mut sim = self.fresh();
        let mut saved: Saved = Vec::new();
        for _ in 0..len {
            self.op(&s, &mut sim, &mut saved)?;
        }
        if self.rng.random_bool(0.5) {
            for (mut p, _) in saved {
                // SAFETY: a state the instance handed out.
                let r = unsafe { s.free_fmu_state(&mut p) };
                self.expect(&s, "FreeFMUState", &sim, Expect::Ok, r)?;
                ensure!(p.is_null(), "FreeFMUState left the pointer set");
            }
        }
        self.free(s)
    }

    /// Free the instance, then (sometimes) call it: refused, nothing written, nothing logged.
    pub(super) fn free(&mut self, mut s: V::Instance) -> Result<()> {
        s.free();
        self.stats.calls += 1;
        if self.rng.random_bool(0.2) {
            let step = s.do_step(0.0, 1.0, false, true);
            let r = [step.status, s.reset(), s.exit_initialization_mode()];
            // Freeing it again is a no-op.
            s.free();
            self.stats.calls += 4;
            self.stats.dead_calls += 4;
            self.stats.statuses[3] += 3;
            ensure!(r == [3, 3, 3], "calls on a freed instance answered {r:?}");
            ensure!(
                step.flags.is_none_or(|f| f == [0xAA; 3])
                    && step.last_successful_time.is_none_or(f64::is_nan),
                "DoStep on a freed instance wrote its outputs"
            );
            let msgs = s.take_messages();
            ensure!(
                msgs.is_empty(),
                "a freed instance logged through its callback: {msgs:?}"
            );
        }
        Ok(())
    }

    /// A null instance is refused by every function (and freed without harm).
    pub(super) fn null_instance(&mut self) -> Result<()> {
        let mut s = self.version.null_instance();
        let (vr, mut x, mut p) = (0u32, 0.0, std::ptr::null_mut());
        s.free();
        let step = s.do_step(0.0, 1.0, false, false);
        let mut r = vec![
            step.status,
            s.terminate(),
            s.reset(),
            s.enter_initialization_mode(None, 0.0, None),
        ];
        // SAFETY: a null instance must refuse every call without using its arguments.
        unsafe {
            r.push(s.get_float64(&vr, 1, &mut x, 1));
            r.push(s.set_debug_logging(1.into(), 0, std::ptr::null()));
            r.push(s.get_fmu_state(&mut p));
        }
        r.extend(V::null_calls(&s));
        self.stats.calls += r.len() + 1;
        self.stats.dead_calls += r.len() + 1;
        self.stats.statuses[3] += r.len();
        ensure!(
            r.iter().all(|&s| s == 3),
            "a null instance was answered {r:?}"
        );
        ensure!(p.is_null(), "GetFMUState of a null instance wrote a state");
        Ok(())
    }

    /// A variable of type `ty` (any type if `None`), or `None` now and then: an unknown
    /// reference.
    pub(super) fn var(&mut self, ty: Option<Type3>) -> Option<Variable> {
        if self.rng.random_bool(0.05) {
            return None;
        }
        let n = self
            .variables
            .iter()
            .filter(|v| ty.is_none_or(|t| v.ty == t))
            .count();
        if n == 0 {
            return None;
        }
        let k = self.rng.random_range(0..n);
        self.variables
            .iter()
            .filter(|v| ty.is_none_or(|t| v.ty == t))
            .nth(k)
            .copied()
    }

    /// The reference of `v`, or an unknown one.
    pub(super) fn vr_of(&mut self, v: &Option<Variable>) -> u32 {
        match v {
            Some(v) => v.vr,
            None if self.rng.random_bool(0.1) => u32::MAX,
            None => self.variables.len() as u32 + self.rng.random_range(0..1000u32),
        }
    }

    /// The variable of table key `key`.
    pub(super) fn key_var(&self, key: Key) -> Option<Variable> {
        let i = self.vars.iter().position(|v| v.key == key)?;
        self.variables.get(i).copied()
    }

    /// The variable that is `what`.
    pub(super) fn extra(&self, what: What) -> Option<Variable> {
        self.variables.iter().find(|v| v.what == what).copied()
    }
}
