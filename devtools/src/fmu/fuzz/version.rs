//! [`Version`]: what the fuzzer needs of an FMI version beyond the shared interface
//! ([`FmiInstance`]): its variables and value types, how an instance is made and initialised,
//! the calls only it has, and its report.

use super::fuzzer::{Fuzzer, Saved};
use super::model::Sim;
use super::values::Vals;
use super::variables::Variable;
use anyhow::Result;
use entrynav_fmi_host::FmiInstance;
use entrynav_fmu::instance::Type3;
use entrynav_fmu::vars::ModelSpec;

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
