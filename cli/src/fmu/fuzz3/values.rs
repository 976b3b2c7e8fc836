//! The FMI 3.0 fuzzer's reads: fmi3Get{VariableType} of every type this FMU has, with unknown and
//! mistyped references, `nValues` that does not match the expanded arrays, null arrays, and the
//! values checked (finite reals, Booleans 0 or 1, strings, `time`, `n_state_slots`); and the
//! arrays compared with the scalar outputs ([`Fuzzer::check_arrays`]).

use super::model::{Expect, Sim, St, V3, What, same_time};
use super::*;
use entrynav_fmu::instance::Type3;
use entrynav_fmu::vars::fmi3::Extra;
use std::ffi::c_char;

/// The types this FMU has, the scalar ones more often.
pub(super) const TYPES: [Type3; 8] = [
    Type3::Float64,
    Type3::Float64,
    Type3::Int32,
    Type3::Int64,
    Type3::UInt64,
    Type3::Boolean,
    Type3::String,
    Type3::Float64,
];

/// The values an fmi3Get call wrote.
pub(super) enum Vals {
    F64(Vec<f64>),
    I32(Vec<i32>),
    I64(Vec<i64>),
    U64(Vec<u64>),
    Bool(Vec<u8>),
    Str(Vec<*const c_char>),
}

impl Fuzzer<'_> {
    /// fmi3Get of type `ty`: `nvr` references at `vrs`, into a buffer of `room` values (null if
    /// `null_values`), with `n_values` as the count.
    ///
    /// # Safety
    /// `vrs` is null or points to `nvr` references; the FMU writes at most `n_values` values and
    /// only when `n_values <= room` (it must refuse any other count unread).
    pub(super) unsafe fn get_raw(
        &self,
        s: &Inst,
        ty: Type3,
        (vrs, nvr): (*const u32, usize),
        room: usize,
        null_values: bool,
        n_values: usize,
    ) -> (i32, Vals) {
        macro_rules! call {
            ($f:ident, $v:ident, $zero:expr) => {{
                let mut buf = vec![$zero; room];
                let p = if null_values {
                    std::ptr::null_mut()
                } else {
                    buf.as_mut_ptr()
                };
                // SAFETY: as the caller guarantees.
                let r = unsafe { (self.api.$f)(s.c, vrs, nvr, p, n_values) };
                (r, Vals::$v(buf))
            }};
        }
        match ty {
            Type3::Float64 => call!(fmi3GetFloat64, F64, 0.0),
            Type3::Int32 => call!(fmi3GetInt32, I32, 0),
            Type3::Int64 => call!(fmi3GetInt64, I64, 0),
            Type3::UInt64 => call!(fmi3GetUInt64, U64, 0),
            Type3::Boolean => call!(fmi3GetBoolean, Bool, 7),
            Type3::String => call!(fmi3GetString, Str, std::ptr::null()),
        }
    }

    /// A read of 0 to 3 variables, mostly of the function's type, now and then an unknown or
    /// mistyped reference or a wrong `nValues`.
    pub(super) fn get(&mut self, s: &Inst, sim: &mut Sim) -> Result<()> {
        let ty = TYPES[self.rng.random_range(0..TYPES.len())];
        let n = [0, 1, 1, 1, 2, 2, 3][self.rng.random_range(0..7)];
        let vars: Vec<Option<V3>> = (0..n)
            .map(|_| {
                let any = self.rng.random_bool(0.1);
                self.var((!any).then_some(ty))
            })
            .collect();
        let vrs: Vec<u32> = vars.iter().map(|v| self.vr_of(v)).collect();
        let count: usize = vars.iter().map(|v| v.map_or(1, |v| v.len)).sum();
        let mut e = sim.get(&self.sc, self.u.model, ty, &vars, &self.vars);
        if vars.iter().any(|v| v.is_none_or(|v| v.ty != ty)) {
            self.stats.bad_refs += 1;
        }
        let n_values = if self.rng.random_bool(0.08) {
            [count + 1, count.wrapping_sub(1), 0, usize::MAX][self.rng.random_range(0..4)]
        } else {
            count
        };
        if n_values != count {
            self.stats.count_mismatches += 1;
            e = Expect::Refused;
        }
        // SAFETY: `n` references; room for `count` values, and any other count is refused.
        let (r, vals) = unsafe { self.get_raw(s, ty, (vrs.as_ptr(), n), count, false, n_values) };
        self.expect(
            s,
            &format!("fmi3Get{}({vrs:?}, nValues {n_values})", ty.name()),
            sim,
            e,
            r,
        )?;
        if r == 0 {
            let vars: Vec<V3> = vars.into_iter().flatten().collect();
            self.check_values(sim, &vars, &vals)?;
            if sim.st == St::Init && Sim::needs_engine(&vars, &self.vars) {
                sim.engine = true;
            }
        }
        Ok(())
    }

    /// What every read value must be: reals finite (outputs read 0 when not finite), Booleans 0
    /// or 1, strings valid, `time` the current time, `n_state_slots` the model's, an
    /// Enumeration one of its items.
    pub(super) fn check_values(&self, sim: &Sim, vars: &[V3], vals: &Vals) -> Result<()> {
        let mut k = 0;
        for v in vars {
            let name = match v.what {
                What::Scalar(i) => self.vars[i].name.as_str(),
                What::Time => "time",
                What::Slots => "n_state_slots",
                What::Array(_) => "an array",
            };
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
                    Vals::I64(x) => {
                        let items = match v.what {
                            What::Scalar(i) => self.vars[i].declared.map(|d| d.items.len()),
                            _ => None,
                        };
                        ensure!(
                            items.is_none_or(|n| (0..n as i64).contains(&x[k])),
                            "{name} read {}, not an item of its Enumeration",
                            x[k]
                        );
                    }
                    Vals::Bool(x) => ensure!(x[k] <= 1, "{name} read the byte {}", x[k]),
                    Vals::Str(x) => {
                        ensure!(!x[k].is_null(), "{name} read a null string");
                        // SAFETY: a C string the FMU keeps valid until the next fmi3GetString.
                        let text = unsafe { CStr::from_ptr(x[k]) };
                        ensure!(
                            text.to_str().is_ok(),
                            "{name} read a string that is not UTF-8"
                        );
                    }
                    Vals::I32(x) => {
                        if let What::Scalar(i) = v.what {
                            match self.vars[i].key {
                                Key::Seed => ensure!(
                                    x[k] == sim.seed,
                                    "seed read {}, expected {}",
                                    x[k],
                                    sim.seed
                                ),
                                Key::NStates => ensure!(
                                    (0..=self.slots as i32).contains(&x[k]),
                                    "n_states read {} with {} slots",
                                    x[k],
                                    self.slots
                                ),
                                _ => {}
                            }
                        }
                    }
                }
                k += 1;
            }
        }
        Ok(())
    }

    /// Null arrays: with a non-zero count they are refused unread; with zero counts the call is
    /// the empty read or write (allowed where the function is).
    pub(super) fn null_arrays(&mut self, s: &Inst, sim: &mut Sim) -> Result<()> {
        let Some(v) = self.var(Some(Type3::Float64)) else {
            return Ok(());
        };
        let (null, nothing) = (std::ptr::null::<u32>(), std::ptr::null::<f64>());
        let mut x = vec![0.0; v.len];
        self.stats.null_arrays += 1;
        // SAFETY: every non-null array has `v.len` elements; null ones go with the counts.
        let (what, r, e) = unsafe {
            match self.rng.random_range(0..5) {
                0 => (
                    "fmi3GetFloat64(NULL references)",
                    (self.api.fmi3GetFloat64)(s.c, null, 2, x.as_mut_ptr(), v.len),
                    Expect::Refused,
                ),
                1 => (
                    "fmi3GetFloat64(NULL values)",
                    (self.api.fmi3GetFloat64)(s.c, &v.vr, 1, std::ptr::null_mut(), v.len),
                    Expect::Refused,
                ),
                2 => (
                    "fmi3SetFloat64(NULL values)",
                    (self.api.fmi3SetFloat64)(s.c, &v.vr, 1, nothing, v.len),
                    Expect::Refused,
                ),
                3 => (
                    "fmi3GetFloat64(nothing, NULL arrays)",
                    (self.api.fmi3GetFloat64)(s.c, null, 0, std::ptr::null_mut(), 0),
                    Expect::ok_if(sim.st.readable()),
                ),
                _ => (
                    "fmi3SetFloat64(nothing, NULL arrays)",
                    (self.api.fmi3SetFloat64)(s.c, null, 0, nothing, 0),
                    Expect::ok_if(sim.st.writable()),
                ),
            }
        };
        self.expect(s, what, sim, e, r)
    }

    /// An array (or, without arrays, a scalar) read with the right `nValues`, one too few, one
    /// too many, 1 or `usize::MAX`.
    pub(super) fn get_nvalues(&mut self, s: &Inst, sim: &mut Sim) -> Result<()> {
        let arrays: Vec<V3> = self
            .v3
            .iter()
            .filter(|v| matches!(v.what, What::Array(_) | What::Time))
            .copied()
            .collect();
        let v = arrays[self.rng.random_range(0..arrays.len())];
        let n_values =
            [v.len, v.len, v.len - 1, v.len + 1, 1, usize::MAX][self.rng.random_range(0..6)];
        let mut e = sim.get(&self.sc, self.u.model, v.ty, &[Some(v)], &self.vars);
        if n_values != v.len {
            self.stats.count_mismatches += 1;
            e = Expect::Refused;
        }
        // SAFETY: one reference; room for `v.len` values (any other count is refused).
        let (r, vals) = unsafe { self.get_raw(s, v.ty, (&v.vr, 1), v.len, false, n_values) };
        self.expect(
            s,
            &format!("fmi3GetFloat64({}, nValues {n_values})", v.vr),
            sim,
            e,
            r,
        )?;
        if r == 0 {
            self.check_values(sim, &[v], &vals)?;
            if sim.st == St::Init && v.what != What::Time {
                sim.engine = true;
            }
        }
        Ok(())
    }

    /// The arrays against the scalar outputs: `est_x` and `est_sigma` bit for bit the scalars
    /// `est_x_i` and `est_sigma_i`, `est_sigma[i]` the square root of the covariance diagonal,
    /// and every element past the filter's dimension (`n_states`) 0.
    pub(super) fn check_arrays(&mut self, s: &Inst, sim: &mut Sim) -> Result<()> {
        let n = self.slots;
        let (Some(x), Some(sigma), Some(cov)) = (
            self.extra(What::Array(Extra::Estimate)),
            self.extra(What::Array(Extra::Sigma)),
            self.extra(What::Array(Extra::Covariance)),
        ) else {
            return Ok(());
        };
        let all = [Some(x), Some(sigma), Some(cov)];
        let e = sim.get(&self.sc, self.u.model, Type3::Float64, &all, &self.vars);
        let count = 2 * n + n * n;
        let vrs = [x.vr, sigma.vr, cov.vr];
        // SAFETY: three references; room for what they hold.
        let (r, arrays) =
            unsafe { self.get_raw(s, Type3::Float64, (vrs.as_ptr(), 3), count, false, count) };
        self.expect(
            s,
            "fmi3GetFloat64(est_x, est_sigma, est_covariance)",
            sim,
            e,
            r,
        )?;
        if r != 0 {
            return Ok(());
        }
        if sim.st == St::Init {
            sim.engine = true;
        }
        let Vals::F64(arrays) = arrays else {
            unreachable!()
        };
        let scalars: Vec<V3> = (0..n)
            .map(|i| self.key_var(Key::EstX(i)))
            .chain((0..n).map(|i| self.key_var(Key::EstSigma(i))))
            .collect::<Option<_>>()
            .context("the model has arrays but not their scalar outputs")?;
        let svrs: Vec<u32> = scalars.iter().map(|v| v.vr).collect();
        // SAFETY: 2n references and room for 2n values.
        let (r, sv) = unsafe {
            self.get_raw(
                s,
                Type3::Float64,
                (svrs.as_ptr(), 2 * n),
                2 * n,
                false,
                2 * n,
            )
        };
        self.expect(
            s,
            "fmi3GetFloat64(est_x_i, est_sigma_i)",
            sim,
            Expect::Ok,
            r,
        )?;
        let Vals::F64(sv) = sv else { unreachable!() };
        let dim = self.key_var(Key::NStates).map(|v| v.vr);
        let mut n_states = n as i32;
        if let Some(vr) = dim {
            // SAFETY: one reference and one value.
            let r = unsafe { (self.api.fmi3GetInt32)(s.c, &vr, 1, &mut n_states, 1) };
            self.expect(s, "fmi3GetInt32(n_states)", sim, Expect::Ok, r)?;
        }
        let dim = usize::try_from(n_states).ok().filter(|&d| d <= n);
        let dim = dim.with_context(|| format!("n_states = {n_states} with {n} slots"))?;
        let (ax, asig, acov) = (&arrays[..n], &arrays[n..2 * n], &arrays[2 * n..]);
        for i in 0..n {
            ensure!(
                ax[i].to_bits() == sv[i].to_bits() && asig[i].to_bits() == sv[n + i].to_bits(),
                "slot {i}: est_x {} / est_sigma {} but the scalars read {} / {} (state {:?}, t = {})",
                ax[i],
                asig[i],
                sv[i],
                sv[n + i],
                sim.st,
                sim.time
            );
            let want = acov[i * n + i].max(0.0).sqrt();
            ensure!(
                (asig[i] - want).abs() <= 1e-12 * asig[i].abs().max(want.abs()),
                "slot {i}: est_sigma {} but sqrt(est_covariance[{i},{i}]) = {want}",
                asig[i]
            );
            if i >= dim {
                let row_col = (0..n).all(|j| acov[i * n + j] == 0.0 && acov[j * n + i] == 0.0);
                ensure!(
                    ax[i] == 0.0 && asig[i] == 0.0 && row_col,
                    "slot {i} is past n_states = {dim} but does not read 0"
                );
            }
        }
        self.stats.array_checks += 1;
        Ok(())
    }
}
