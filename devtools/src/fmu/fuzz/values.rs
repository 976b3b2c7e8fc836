//! The fuzzer's reads: a getter of every value type the version has, with unknown and mistyped
//! references, (FMI 3.0) a `nValues` that does not match what the references hold, and the
//! values checked (finite reals, Booleans 0 or 1, valid strings, `time`, `n_state_slots`, the
//! seed, an Enumeration one of its items).

use super::fuzzer::{Fuzzer, Version};
use super::model::{Expect, Sim, St, same_time};
use super::vals::Vals;
use super::variables::{Variable, What};
use anyhow::{Context, Result, ensure};
use entrynav_fmi_host::FmiInstance;
use entrynav_fmu::instance::Type3;
use entrynav_fmu::vars::Key;
use rand::RngExt;
use std::ffi::CStr;

impl<V: Version> Fuzzer<V> {
    /// A getter of type `ty`: `nvr` references at `vrs`, into a buffer of `room` values (null if
    /// `null_values`), with `n_values` as the count.
    ///
    /// # Safety
    /// `vrs` is null or points to `nvr` references; the FMU writes at most `n_values` values and
    /// only when `n_values <= room` (it must refuse any other count unread); FMI 2.0 (no
    /// `nValues`): `n_values == nvr <= room`.
    pub(super) unsafe fn get_raw(
        &self,
        s: &V::Instance,
        ty: Type3,
        (vrs, nvr): (*const u32, usize),
        room: usize,
        null_values: bool,
        n_values: usize,
    ) -> Result<(i32, Vals)> {
        macro_rules! call {
            ($f:ident, $zero:expr) => {{
                let mut buf = vec![$zero; room];
                let p = if null_values {
                    std::ptr::null_mut()
                } else {
                    buf.as_mut_ptr()
                };
                // SAFETY: as the caller guarantees.
                (unsafe { s.$f(vrs, nvr, p, n_values) }, buf)
            }};
        }
        Ok(match ty {
            Type3::Float64 => {
                let (r, b) = call!(get_float64, 0.0);
                (r, Vals::F64(b))
            }
            Type3::Int32 => {
                let (r, b) = call!(get_int32, 0);
                (r, Vals::I32(b))
            }
            Type3::Boolean => {
                let (r, b) = call!(get_boolean, 7u8.into());
                (r, Vals::Bool(b.into_iter().map(Into::into).collect()))
            }
            Type3::String => {
                let (r, b) = call!(get_string, std::ptr::null());
                (r, Vals::Str(b))
            }
            Type3::Int64 | Type3::UInt64 => {
                // SAFETY: as the caller guarantees.
                unsafe { V::get_other(s, ty, (vrs, nvr), room, null_values, n_values) }
                    .with_context(|| format!("this FMI version has no {ty:?} getter"))?
            }
        })
    }

    /// A read of 0 to 3 variables, mostly of the getter's type, now and then an unknown or
    /// mistyped reference or (FMI 3.0) a wrong `nValues`.
    pub(super) fn get(&mut self, s: &V::Instance, sim: &mut Sim) -> Result<()> {
        let ty = V::TYPES[self.rng.random_range(0..V::TYPES.len())];
        let n = [0, 1, 1, 1, 2, 2, 3][self.rng.random_range(0..7)];
        let vars: Vec<Option<Variable>> = (0..n)
            .map(|_| {
                let any = self.rng.random_bool(0.1);
                self.var((!any).then_some(ty))
            })
            .collect();
        let vrs: Vec<u32> = vars.iter().map(|v| self.vr_of(v)).collect();
        let count: usize = vars.iter().map(|v| v.map_or(1, |v| v.len)).sum();
        let mut e = sim.get(&self.sc, self.model, ty, &vars, &self.vars);
        if vars.iter().any(|v| v.is_none_or(|v| v.ty != ty)) {
            self.stats.bad_refs += 1;
        }
        let n_values = if V::N_VALUES && self.rng.random_bool(0.08) {
            [count + 1, count.wrapping_sub(1), 0, usize::MAX][self.rng.random_range(0..4)]
        } else {
            count
        };
        if n_values != count {
            self.stats.count_mismatches += 1;
            e = Expect::Refused;
        }
        // SAFETY: `n` references; room for `count` values, and any other count is refused.
        let (r, vals) = unsafe { self.get_raw(s, ty, (vrs.as_ptr(), n), count, false, n_values)? };
        self.expect(
            s,
            &format!("Get{}({vrs:?}, nValues {n_values})", ty.name()),
            sim,
            e,
            r,
        )?;
        if r == 0 {
            let vars: Vec<Variable> = vars.into_iter().flatten().collect();
            self.check_values(sim, &vars, &vals)?;
            if sim.st == St::Init && Sim::needs_engine(&vars, &self.vars) {
                sim.engine = true;
            }
        }
        Ok(())
    }

    /// The name of `v` in messages.
    fn name_of(&self, v: &Variable) -> &str {
        match v.what {
            What::Scalar(i) => self.vars[i].name.as_str(),
            What::Time => "time",
            What::Slots => "n_state_slots",
            What::Array(_) => "an array",
        }
    }

    /// What every read value must be: reals finite (outputs read 0 when not finite), Booleans 0
    /// or 1, strings valid, `time` the current time, `n_state_slots` the model's, the seed the one
    /// set, an Enumeration one of its items.
    pub(super) fn check_values(&self, sim: &Sim, vars: &[Variable], vals: &Vals) -> Result<()> {
        let mut k = 0;
        for v in vars {
            let name = self.name_of(v);
            for _ in 0..v.len {
                match vals {
                    Vals::F64(x) => {
                        ensure!(x[k].is_finite(), "{name} read {}", x[k]);
                        if v.what == What::Time
                            && matches!(sim.st, St::Init | St::Step | St::Terminated)
                        {
                            ensure!(
                                same_time(x[k], sim.time),
                                "time read {} in state {:?}, expected {}",
                                x[k],
                                sim.st,
                                sim.time
                            );
                        }
                    }
                    Vals::U64(x) => ensure!(
                        x[k] == self.slots as u64,
                        "n_state_slots read {}, expected {}",
                        x[k],
                        self.slots
                    ),
                    Vals::I32(_) | Vals::I64(_) => self.check_integer(sim, v, vals, k)?,
                    Vals::Bool(x) => {
                        ensure!((0..=1).contains(&x[k]), "{name} read the Boolean {}", x[k])
                    }
                    Vals::Str(x) => {
                        ensure!(!x[k].is_null(), "{name} read a null string");
                        // SAFETY: a C string the FMU keeps valid until the next string read.
                        let text = unsafe { CStr::from_ptr(x[k]) };
                        ensure!(
                            text.to_str().is_ok(),
                            "{name} read a string that is not UTF-8"
                        );
                    }
                }
                k += 1;
            }
        }
        Ok(())
    }

    /// An integer read: an Enumeration one of its items, the seed the one set, `n_states` at
    /// most the slots.
    fn check_integer(&self, sim: &Sim, v: &Variable, vals: &Vals, k: usize) -> Result<()> {
        let What::Scalar(i) = v.what else {
            return Ok(());
        };
        let (var, x) = (&self.vars[i], vals.integer(k).unwrap_or_default());
        if let Some(d) = var.declared {
            ensure!(
                (0..d.items.len() as i64).contains(&x),
                "{} read {x}, not an item of its Enumeration",
                var.name
            );
            return Ok(());
        }
        match var.key {
            Key::Seed => ensure!(x == sim.seed as i64, "seed read {x}, expected {}", sim.seed),
            Key::NStates => ensure!(
                (0..=self.slots as i64).contains(&x),
                "n_states read {x} with {} slots",
                self.slots
            ),
            _ => {}
        }
        Ok(())
    }
}
