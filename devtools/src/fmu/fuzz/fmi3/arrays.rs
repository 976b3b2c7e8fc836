//! The FMI 3.0 arrays and wide integers: `nValues` against the expanded length of an array,
//! the arrays `est_x`, `est_sigma` and `est_covariance` against the scalar outputs, and the
//! Int64 (Enumerations, values past Int32) and UInt64 (the structural parameter) setters.

use super::super::fuzzer::Fuzzer;
use super::super::model::{Expect, Sim, St};
use super::super::vals::Vals;
use super::super::variables::{Variable, What};
use super::Fmi3;
use anyhow::{Context, Result, ensure};
use entrynav_fmi_host::Slave3;
use entrynav_fmu::instance::Type3;
use entrynav_fmu::vars::Key;
use entrynav_fmu::vars::fmi3::Extra;
use rand::RngExt;

/// Int64 values, past the Int32 range included.
const INT64S: [i64; 6] = [0, 1, 2, i64::MAX, i64::MIN, 1 << 31];

impl Fuzzer<Fmi3> {
    /// An array (or, without arrays, a scalar) read with the right `nValues`, one too few, one
    /// too many, 1 or `usize::MAX`.
    pub(super) fn get_nvalues(&mut self, s: &Slave3, sim: &mut Sim) -> Result<()> {
        let arrays: Vec<Variable> = self
            .variables
            .iter()
            .filter(|v| matches!(v.what, What::Array(_) | What::Time))
            .copied()
            .collect();
        let v = arrays[self.rng.random_range(0..arrays.len())];
        let n_values =
            [v.len, v.len, v.len - 1, v.len + 1, 1, usize::MAX][self.rng.random_range(0..6)];
        let mut e = sim.get(&self.sc, self.model, v.ty, &[Some(v)], &self.vars);
        if n_values != v.len {
            self.stats.count_mismatches += 1;
            e = Expect::Refused;
        }
        // SAFETY: one reference; room for `v.len` values (any other count is refused).
        let (r, vals) = unsafe { self.get_raw(s, v.ty, (&v.vr, 1), v.len, false, n_values)? };
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
    pub(super) fn check_arrays(&mut self, s: &Slave3, sim: &mut Sim) -> Result<()> {
        let n = self.slots;
        let (Some(x), Some(sigma), Some(cov)) = (
            self.extra(What::Array(Extra::Estimate)),
            self.extra(What::Array(Extra::Sigma)),
            self.extra(What::Array(Extra::Covariance)),
        ) else {
            return Ok(());
        };
        let all = [Some(x), Some(sigma), Some(cov)];
        let e = sim.get(&self.sc, self.model, Type3::Float64, &all, &self.vars);
        let count = 2 * n + n * n;
        let vrs = [x.vr, sigma.vr, cov.vr];
        // SAFETY: three references; room for what they hold.
        let (r, arrays) =
            unsafe { self.get_raw(s, Type3::Float64, (vrs.as_ptr(), 3), count, false, count)? };
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
        let scalars: Vec<Variable> = (0..n)
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
            )?
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
            let r = unsafe { (s.api.fmi3GetInt32)(s.c, &vr, 1, &mut n_states, 1) };
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

    /// fmi3SetInt64 of values past the Int32 range (Enumerations, or a mistyped Int32), or
    /// fmi3SetUInt64 of the structural parameter (only its own value is accepted).
    pub(super) fn set_wide(&mut self, s: &Slave3, sim: &mut Sim) -> Result<()> {
        let api = std::sync::Arc::clone(&s.api);
        let (name, ty, v, valid, r) = if self.rng.random_bool(0.5) {
            let any = self.rng.random_bool(0.3);
            let v = self.var(Some(if any { Type3::Int32 } else { Type3::Int64 }));
            let x = INT64S[self.rng.random_range(0..INT64S.len())];
            let vr = self.vr_of(&v);
            // SAFETY: one reference and one value.
            let r = unsafe { (api.fmi3SetInt64)(s.c, &vr, 1, &x, 1) };
            ("fmi3SetInt64", Type3::Int64, v, i32::try_from(x).is_ok(), r)
        } else {
            let v = self.var(Some(Type3::UInt64));
            let n = self.slots as u64;
            let x = [n, n, 0, n + 1, u64::MAX, (1 << 32) + n][self.rng.random_range(0..6)];
            let vr = self.vr_of(&v);
            // SAFETY: one reference and one value.
            let r = unsafe { (api.fmi3SetUInt64)(s.c, &vr, 1, &x, 1) };
            ("fmi3SetUInt64", Type3::UInt64, v, x == n, r)
        };
        let e = self.set_expect(sim, ty, &[(v, valid)], 1);
        self.expect(s, &format!("{name}({:?})", v.map(|v| v.vr)), sim, e, r)
    }
}
