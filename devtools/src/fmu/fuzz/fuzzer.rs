//! [`Fuzzer`]: one FMU under test through one FMI version, its random number generator and the
//! facts the model needs; [`Version`]: what the fuzzer needs of an FMI version beyond the shared
//! interface ([`FmiInstance`]): its variables and value types, how an instance is made and
//! initialised, the calls only it has, and its report. The check of every answer is in
//! [`super::answers`], the sequences and the calls on freed and null instances in
//! [`super::sequence`].

use super::model::Sim;
use super::scenarios::Scenarios;
use super::stats::Stats;
use super::vals::Vals;
use super::variables::{Variable, What};
use crate::fmu::defaults::start_params;
use anyhow::{Result, ensure};
use entrynav_fmi_host::{FmiInstance, FmuState};
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
    pub(super) names: HashSet<&'static str>,
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

/// One FMI version as the fuzzer drives it.
pub(super) trait Version: Sized {
    /// The instance of this version.
    type Instance: FmiInstance;
    /// The prefix of the other version's names, which no message may use.
    const OTHER_PREFIX: &'static str;
    /// The value types a random read draws from (the common ones more often).
    const TYPES: &'static [Type3];
    /// Whether the version's getters and setters take `nValues` (FMI 3.0), so that a wrong one
    /// can be passed.
    const N_VALUES: bool;
    /// How many calls only this version has ([`Version::special`] `0..SPECIAL_OPS`).
    const SPECIAL_OPS: u32;

    /// The variables of `spec`'s description of this version (index = value reference).
    fn variables(spec: &ModelSpec) -> Vec<Variable>;
    /// The names of this version (functions and types) a message may use.
    fn names() -> Vec<&'static str>;
    /// A fresh instance named `name`, the model's token and resources, logging on or off; the
    /// FMU must not refuse it.
    fn instantiate(f: &mut Fuzzer<Self>, name: &str, logging_on: bool) -> Result<Self::Instance>;
    /// An instance whose handle is null.
    fn null_instance(&self) -> Self::Instance;
    /// The calls a null instance must refuse besides the shared ones (returns the statuses).
    fn null_calls(s: &Self::Instance) -> Vec<i32>;
    /// Set up the experiment and enter Initialization Mode (FMI 2.0: one of its two calls).
    fn initialise(f: &mut Fuzzer<Self>, s: &Self::Instance, sim: &mut Sim) -> Result<()>;
    /// What the version checks after a successful step (FMI 3.0: now and then the arrays).
    fn after_step(f: &mut Fuzzer<Self>, s: &Self::Instance, sim: &mut Sim) -> Result<()>;
    /// Call `k` of the calls only this version has.
    fn special(
        f: &mut Fuzzer<Self>,
        k: u32,
        s: &Self::Instance,
        sim: &mut Sim,
        saved: &mut Saved,
    ) -> Result<()>;
    /// A getter of a type the shared interface does not have (FMI 3.0: Int64, UInt64; `None`:
    /// the version has no such type).
    ///
    /// # Safety
    /// As [`FmiInstance::get_float64`], with room for `room` values.
    unsafe fn get_other(
        s: &Self::Instance,
        ty: Type3,
        vrs: (*const u32, usize),
        room: usize,
        null_values: bool,
        n_values: usize,
    ) -> Option<(i32, Vals)>;
    /// The line the run ends with.
    fn report(f: &Fuzzer<Self>, seconds: f64) -> String;
}
