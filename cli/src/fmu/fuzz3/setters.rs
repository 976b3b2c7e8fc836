//! The FMI 3.0 fuzzer's writes: fmi3SetFloat64 (the filter FMU's measurement time often; `time`
//! and the arrays, which cannot be set), fmi3SetBoolean (any byte), fmi3SetInt32 (the seed; the
//! Enumerations, which are Int64), fmi3SetInt64 (values past Int32), fmi3SetUInt64 (the
//! structural parameter: only its own value) and fmi3SetString (valid, invalid, over-long, null
//! and non-UTF-8 values).

use super::model::{Expect, Sim, V3};
use super::*;
use entrynav_fmu::instance::Type3;
use entrynav_fmu::limits::MAX_STRING_BYTES;

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
/// Int64 values, past the Int32 range included.
const INT64S: [i64; 6] = [0, 1, 2, i64::MAX, i64::MIN, 1 << 31];
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

impl Fuzzer<'_> {
    /// The outcome of a set of `vars`, each with whether its values pass the FMU's checks, and
    /// `n_values` against the count they hold.
    fn set_expect(
        &mut self,
        sim: &Sim,
        ty: Type3,
        vars: &[(Option<V3>, bool)],
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

    /// `count`, or now and then another `nValues`.
    fn n_values(&mut self, count: usize) -> usize {
        if self.rng.random_bool(0.05) {
            [count + 1, count.wrapping_sub(1), 0][self.rng.random_range(0..3)]
        } else {
            count
        }
    }

    /// A Float64 variable, the filter FMU's measurement time often; sometimes two.
    pub(super) fn set_float64(&mut self, s: &Inst, sim: &mut Sim) -> Result<()> {
        let n = if self.rng.random_bool(0.15) { 2 } else { 1 };
        let meas = self.key_var(Key::MeasTime).map(|v| v.vr);
        let mut vars = Vec::new();
        let mut values = Vec::new();
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
                values.push(if is_meas {
                    let t = sim.time;
                    [
                        t,
                        t + 0.1,
                        t * 0.5,
                        -5.0,
                        0.0,
                        1e9,
                        1e18,
                        1e300,
                        301.0,
                        5e-324,
                    ][self.rng.random_range(0..10)]
                } else {
                    REALS[self.rng.random_range(0..REALS.len())]
                });
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
        // SAFETY: `n` references and `count + 1` values (any count but `count` is refused).
        let r =
            unsafe { (self.api.fmi3SetFloat64)(s.c, vrs.as_ptr(), n, values.as_ptr(), n_values) };
        self.expect(
            s,
            &format!(
                "fmi3SetFloat64({vrs:?}, {:?}, nValues {n_values})",
                &values[..count]
            ),
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

    /// A Boolean variable (the filter FMU's epoch flag often) to a byte: 0, 1 or another
    /// (true).
    pub(super) fn set_boolean(&mut self, s: &Inst, sim: &mut Sim) -> Result<()> {
        let epoch = self
            .key_var(Key::MeasEpoch)
            .filter(|_| self.rng.random_bool(0.4));
        let v = epoch.or_else(|| self.var(Some(Type3::Boolean)));
        let b = [0u8, 1, 0, 1, 2, 255][self.rng.random_range(0..6)];
        let vr = self.vr_of(&v);
        let n_values = self.n_values(1);
        let e = self.set_expect(sim, Type3::Boolean, &[(v, true)], n_values);
        let bytes = [b, b];
        // SAFETY: one reference and two values (a count over one is refused).
        let r = unsafe { (self.api.fmi3SetBoolean)(s.c, &vr, 1, bytes.as_ptr(), n_values) };
        self.expect(s, &format!("fmi3SetBoolean({vr}, {b})"), sim, e, r)?;
        if e == Expect::Ok
            && let Some(super::model::What::Scalar(i)) = v.map(|v| v.what)
        {
            match self.vars[i].key {
                Key::MeasEpoch => sim.meas_epoch = b != 0,
                Key::Dispersed | Key::AllowExternalFiles => sim.engine = false,
                _ => {}
            }
        }
        Ok(())
    }

    /// fmi3SetInt32 of a random Int32 or Enumeration variable, fmi3SetInt64 of values past the
    /// Int32 range, or fmi3SetUInt64 of the structural parameter.
    pub(super) fn set_integer(&mut self, s: &Inst, sim: &mut Sim) -> Result<()> {
        let api = self.api;
        let mut seed = None;
        let (name, ty, v, valid, r) = match self.rng.random_range(0..3) {
            0 => {
                let any = self.rng.random_bool(0.3);
                let v = self.var(Some(if any { Type3::Int64 } else { Type3::Int32 }));
                let x = SEEDS[self.rng.random_range(0..SEEDS.len())];
                let vr = self.vr_of(&v);
                // SAFETY: one reference and one value.
                let r = unsafe { (api.fmi3SetInt32)(s.c, &vr, 1, &x, 1) };
                let is =
                    |key: Key| v.is_some() && v.map(|v| v.vr) == self.key_var(key).map(|s| s.vr);
                let is_seed = is(Key::Seed);
                if is_seed {
                    seed = Some(x);
                }
                // The guided FMU's Monte Carlo run index.
                let valid = if is(Key::Run) {
                    (0..=entrynav_fmu::limits::MAX_RUN).contains(&x)
                } else {
                    !is_seed || x >= 0
                };
                ("fmi3SetInt32", Type3::Int32, v, valid, r)
            }
            1 => {
                let any = self.rng.random_bool(0.3);
                let v = self.var(Some(if any { Type3::Int32 } else { Type3::Int64 }));
                let x = INT64S[self.rng.random_range(0..INT64S.len())];
                let vr = self.vr_of(&v);
                // SAFETY: one reference and one value.
                let r = unsafe { (api.fmi3SetInt64)(s.c, &vr, 1, &x, 1) };
                ("fmi3SetInt64", Type3::Int64, v, i32::try_from(x).is_ok(), r)
            }
            _ => {
                let v = self.var(Some(Type3::UInt64));
                let n = self.slots as u64;
                let x = [n, n, 0, n + 1, u64::MAX, (1 << 32) + n][self.rng.random_range(0..6)];
                let vr = self.vr_of(&v);
                // SAFETY: one reference and one value.
                let r = unsafe { (api.fmi3SetUInt64)(s.c, &vr, 1, &x, 1) };
                ("fmi3SetUInt64", Type3::UInt64, v, x == n, r)
            }
        };
        let e = self.set_expect(sim, ty, &[(v, valid)], 1);
        self.expect(s, &format!("{name}({:?})", v.map(|v| v.vr)), sim, e, r)?;
        if e == Expect::Ok
            && let Some(x) = seed
            && x != sim.seed
        {
            (sim.seed, sim.engine) = (x, false);
        }
        Ok(())
    }

    /// Set `scenario` or `filter` (fmi3SetString) or `seed` (fmi3SetInt32) to a valid, invalid or
    /// over-long value (a null or non-UTF-8 string too).
    pub(super) fn set_param(&mut self, s: &Inst, sim: &mut Sim) -> Result<()> {
        let api = self.api;
        let which = self.rng.random_range(0..3);
        if which == 2 {
            let x = SEEDS[self.rng.random_range(0..SEEDS.len())];
            let v = self.key_var(Key::Seed);
            let vr = self.vr_of(&v);
            let e = self.set_expect(sim, Type3::Int32, &[(v, x >= 0)], 1);
            // SAFETY: one reference and one value.
            let r = unsafe { (api.fmi3SetInt32)(s.c, &vr, 1, &x, 1) };
            self.expect(s, &format!("fmi3SetInt32(seed, {x})"), sim, e, r)?;
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
        // None: a null pointer; Some(bytes): the string (non-UTF-8 bytes allowed).
        let value: Option<Vec<u8>> = match (key, self.rng.random_range(0..12)) {
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
                let all = entrynav::estimation::nav::FilterKind::ALL;
                Some(all[self.rng.random_range(0..all.len())].name().into())
            }
        };
        let text = value.as_deref().and_then(|b| std::str::from_utf8(b).ok());
        if value.as_ref().is_some_and(|b| b.len() > MAX_STRING_BYTES) {
            self.stats.over_bound += 1;
        }
        let valid = text.is_some_and(|t| {
            t.len() <= MAX_STRING_BYTES
                && !t.trim().is_empty()
                && (key == Key::Scenario || entrynav::estimation::nav::FilterKind::parse(t).is_ok())
        });
        let v = self.key_var(key);
        let vr = self.vr_of(&v);
        let e = self.set_expect(sim, Type3::String, &[(v, valid)], 1);
        let c = value.clone().map(CString::new).transpose()?;
        let p = c.as_ref().map_or(std::ptr::null(), |c| c.as_ptr());
        // SAFETY: one reference and one C string (or null, which is refused).
        let r = unsafe { (api.fmi3SetString)(s.c, &vr, 1, &p, 1) };
        let shown: Option<String> = text.map(|t| t.chars().take(40).collect());
        self.expect(s, &format!("fmi3SetString({key:?}, {shown:?})"), sim, e, r)?;
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
