//! The fuzzer's writes: Float64 (the filter FMU's measurement time often; `time` and the
//! arrays, which cannot be set), Boolean (any byte), Int32 (the seed, the guided FMU's run; the
//! Enumerations, which FMI 3.0 writes as Int64) and the string parameters (valid, invalid,
//! over-long, null and non-UTF-8 values).

use super::fuzzer::{Fuzzer, Version};
use super::model::{Expect, Sim};
use super::variables::{Variable, What};
use anyhow::Result;
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::BUILTIN_NAMES;
use entrynav_fmi_host::FmiInstance;
use entrynav_fmu::instance::Type3;
use entrynav_fmu::limits::{MAX_RUN, MAX_STRING_BYTES};
use entrynav_fmu::vars::Key;
use rand::RngExt;
use std::ffi::CString;

/// Real values.
const REALS: [f64; 9] = [
    0.1,
    -0.4,
    0.0,
    0.35,
    1e308,
    -1e308,
    5e-324,
    f64::NAN,
    f64::INFINITY,
];
/// Seeds.
const SEEDS: [i32; 7] = [0, 1, 7, 12345, i32::MAX, -1, i32::MIN];
/// Scenario values that never load (files that do not exist, host files, escapes).
const BAD_SCENARIOS: [&str; 5] = [
    "nonexistent.toml",
    "/etc/passwd",
    "../../../../../../etc/passwd",
    "sub/../../x.toml",
    "/dev/zero",
];
/// Filter names that are not filters.
const BAD_FILTERS: [&str; 2] = ["kalman", "ekf2"];

impl<V: Version> Fuzzer<V> {
    /// The outcome of a set of `vars`, each with whether its values pass the FMU's checks, and
    /// `n_values` against the count they hold.
    pub(super) fn set_expect(
        &mut self,
        sim: &Sim,
        ty: Type3,
        vars: &[(Option<Variable>, bool)],
        n_values: usize,
    ) -> Expect {
        let count: usize = vars.iter().map(|(v, _)| v.map_or(1, |v| v.len)).sum();
        if vars.iter().any(|(v, _)| v.is_none_or(|v| v.ty != ty)) {
            self.stats.bad_refs += 1;
        }
        if n_values != count {
            self.stats.count_mismatches += 1;
            return Expect::Refused;
        }
        Expect::ok_if(
            vars.iter()
                .all(|&(v, valid)| sim.set_one(v, ty, valid, &self.vars)),
        )
    }

    /// `count`, or (FMI 3.0) now and then another `nValues`.
    fn n_values(&mut self, count: usize) -> usize {
        if V::N_VALUES && self.rng.random_bool(0.05) {
            [count + 1, count.wrapping_sub(1), 0][self.rng.random_range(0..3)]
        } else {
            count
        }
    }

    /// A value for the measurement time (`meas`) or another Float64 variable.
    fn real_value(&mut self, meas: bool, now: f64) -> f64 {
        if meas {
            let pool = [
                now,
                now + 0.1,
                now * 0.5,
                -5.0,
                0.0,
                1e9,
                1e18,
                1e300,
                301.0,
                5e-324,
            ];
            pool[self.rng.random_range(0..pool.len())]
        } else {
            REALS[self.rng.random_range(0..REALS.len())]
        }
    }

    /// A Float64 variable, the filter FMU's measurement time often; sometimes two.
    pub(super) fn set_float64(&mut self, s: &V::Instance, sim: &mut Sim) -> Result<()> {
        let n = if self.rng.random_bool(0.15) { 2 } else { 1 };
        let meas = self.key_var(Key::MeasTime).map(|v| v.vr);
        let (mut vars, mut values) = (Vec::new(), Vec::new());
        // The value the measurement time is set to, if it is among the references.
        let mut meas_value = None;
        for _ in 0..n {
            let v = match self.rng.random_bool(0.4) {
                true => self.key_var(Key::MeasTime),
                false => None,
            };
            let any = self.rng.random_bool(0.05);
            let v = v.or_else(|| self.var((!any).then_some(Type3::Float64)));
            let is_meas = meas.is_some() && v.map(|v| v.vr) == meas;
            let start = values.len();
            for _ in 0..v.map_or(1, |v| v.len) {
                let x = self.real_value(is_meas, sim.time);
                values.push(x);
            }
            if is_meas {
                meas_value = Some(values[start]);
            }
            let valid = values[start..].iter().all(|x: &f64| x.is_finite());
            vars.push((v, valid));
        }
        let vrs: Vec<u32> = vars.iter().map(|(v, _)| self.vr_of(v)).collect();
        let count = values.len();
        let n_values = self.n_values(count);
        let e = self.set_expect(sim, Type3::Float64, &vars, n_values);
        // Room for one value more than the references hold (a larger count is refused unread).
        values.push(0.0);
        // SAFETY: `n` references and `count + 1` values (any count but `count` is refused; FMI
        // 2.0: `count` is `n`).
        let r = unsafe { s.set_float64(vrs.as_ptr(), n, values.as_ptr(), n_values) };
        let shown = &values[..count];
        self.expect(
            s,
            &format!("SetFloat64({vrs:?}, {shown:?}, nValues {n_values})"),
            sim,
            e,
            r,
        )?;
        if e == Expect::Ok
            && let Some(x) = meas_value
        {
            sim.meas_time = x;
        }
        Ok(())
    }

    /// A Boolean variable (the filter FMU's epoch flag often) to 0, 1 or another value (true).
    pub(super) fn set_boolean(&mut self, s: &V::Instance, sim: &mut Sim) -> Result<()> {
        let epoch = self
            .key_var(Key::MeasEpoch)
            .filter(|_| self.rng.random_bool(0.4));
        let v = epoch.or_else(|| self.var(Some(Type3::Boolean)));
        let b = [0u8, 1, 0, 1, 2, 255][self.rng.random_range(0..6)];
        let vr = self.vr_of(&v);
        let n_values = self.n_values(1);
        let e = self.set_expect(sim, Type3::Boolean, &[(v, true)], n_values);
        let values = [b.into(), b.into()];
        // SAFETY: one reference and two values (a count over one is refused).
        let r = unsafe { s.set_boolean(&vr, 1, values.as_ptr(), n_values) };
        self.expect(s, &format!("SetBoolean({vr}, {b})"), sim, e, r)?;
        if e == Expect::Ok
            && let Some(What::Scalar(i)) = v.map(|v| v.what)
        {
            match self.vars[i].key {
                Key::MeasEpoch => sim.meas_epoch = b != 0,
                Key::Dispersed | Key::AllowExternalFiles => sim.engine = false,
                _ => {}
            }
        }
        Ok(())
    }

    /// An Int32 variable (an Enumeration now and then, refused in FMI 3.0 where it is Int64) to
    /// a seed-like value: the seed must be >= 0, the guided FMU's run in 0..=MAX_RUN.
    pub(super) fn set_int32(&mut self, s: &V::Instance, sim: &mut Sim) -> Result<()> {
        let any = self.rng.random_bool(0.3);
        let v = self.var(if any { None } else { Some(Type3::Int32) });
        let x = SEEDS[self.rng.random_range(0..SEEDS.len())];
        let vr = self.vr_of(&v);
        let is = |key: Key| v.is_some() && v.map(|v| v.vr) == self.key_var(key).map(|s| s.vr);
        let is_seed = is(Key::Seed);
        let valid = if is(Key::Run) {
            (0..=MAX_RUN).contains(&x)
        } else {
            !is_seed || x >= 0
        };
        let e = self.set_expect(sim, Type3::Int32, &[(v, valid)], 1);
        // SAFETY: one reference and one value.
        let r = unsafe { s.set_int32(&vr, 1, &x, 1) };
        self.expect(
            s,
            &format!("SetInt32({:?}, {x})", v.map(|v| v.vr)),
            sim,
            e,
            r,
        )?;
        if e == Expect::Ok && is_seed && x != sim.seed {
            (sim.seed, sim.engine) = (x, false);
        }
        Ok(())
    }

    /// A value of the `scenario` or `filter` parameter: `None` a null pointer, else the bytes
    /// (non-UTF-8 ones allowed).
    fn param_value(&mut self, key: Key) -> Option<Vec<u8>> {
        match (key, self.rng.random_range(0..12)) {
            (_, 0) => Some("a".repeat(MAX_STRING_BYTES + 1).into_bytes()),
            (_, 1) => Some(Vec::new()),
            (_, 2) => None,
            (_, 3) => Some(b"four-beacon-fusion\xff".to_vec()),
            (Key::Scenario, 4..=5) => {
                Some(BAD_SCENARIOS[self.rng.random_range(0..BAD_SCENARIOS.len())].into())
            }
            (Key::Scenario, _) => {
                Some(BUILTIN_NAMES[self.rng.random_range(0..BUILTIN_NAMES.len())].into())
            }
            (_, 4) => Some(BAD_FILTERS[self.rng.random_range(0..BAD_FILTERS.len())].into()),
            _ => {
                let all = FilterKind::ALL;
                Some(all[self.rng.random_range(0..all.len())].name().into())
            }
        }
    }

    /// Set `scenario` or `filter` (SetString) or `seed` (SetInt32) to a valid, invalid or
    /// over-long value (a null or non-UTF-8 string too).
    pub(super) fn set_param(&mut self, s: &V::Instance, sim: &mut Sim) -> Result<()> {
        let which = self.rng.random_range(0..3);
        if which == 2 {
            let x = SEEDS[self.rng.random_range(0..SEEDS.len())];
            let v = self.key_var(Key::Seed);
            let vr = self.vr_of(&v);
            let e = self.set_expect(sim, Type3::Int32, &[(v, x >= 0)], 1);
            // SAFETY: one reference and one value.
            let r = unsafe { s.set_int32(&vr, 1, &x, 1) };
            self.expect(s, &format!("SetInt32(seed, {x})"), sim, e, r)?;
            if e == Expect::Ok && x != sim.seed {
                (sim.seed, sim.engine) = (x, false);
            }
            return Ok(());
        }
        let key = if which == 0 {
            Key::Scenario
        } else {
            Key::Filter
        };
        let value = self.param_value(key);
        let text = value.as_deref().and_then(|b| std::str::from_utf8(b).ok());
        if value.as_ref().is_some_and(|b| b.len() > MAX_STRING_BYTES) {
            self.stats.over_bound += 1;
        }
        let valid = text.is_some_and(|t| {
            t.len() <= MAX_STRING_BYTES
                && !t.trim().is_empty()
                && (key == Key::Scenario || FilterKind::parse(t).is_ok())
        });
        let v = self.key_var(key);
        let vr = self.vr_of(&v);
        let e = self.set_expect(sim, Type3::String, &[(v, valid)], 1);
        let c = value.clone().map(CString::new).transpose()?;
        let p = c.as_ref().map_or(std::ptr::null(), |c| c.as_ptr());
        // SAFETY: one reference and one C string (or null, which is refused).
        let r = unsafe { s.set_string(&vr, 1, &p, 1) };
        let shown: Option<String> = text.map(|t| t.chars().take(40).collect());
        self.expect(s, &format!("SetString({key:?}, {shown:?})"), sim, e, r)?;
        if e == Expect::Ok
            && let Some(t) = text
        {
            let field = if key == Key::Scenario {
                &mut sim.scenario
            } else {
                &mut sim.filter
            };
            if field != t {
                *field = t.to_string();
                sim.engine = false;
            }
        }
        Ok(())
    }
}
