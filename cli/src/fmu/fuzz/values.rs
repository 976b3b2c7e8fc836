//! The fuzzer's fmi2Set* calls: inputs (the filter FMU's measurement time and epoch flag often),
//! and parameters with valid, invalid and over-long values (see [`super::ops`]).

use super::model::{Expect, Sim};
use super::*;
use entrynav_fmu::limits::MAX_STRING_BYTES;
use std::ffi::{CString, c_int};

/// Real input values.
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

impl Fuzzer<'_> {
    pub(super) fn set_real(&mut self, s: &Slave, sim: &mut Sim, seen: usize) -> Result<()> {
        // The filter FMU's measurement time is the input that sizes its work: set it often.
        let meas_time = self
            .key_vr(Key::MeasTime)
            .filter(|_| self.rng.random_bool(0.4));
        let v = match meas_time {
            Some(vr) => self.vars.get(vr as usize).cloned(),
            None => self.var(Some(Type::Real)),
        };
        let x = if v.as_ref().is_some_and(|v| v.key == Key::MeasTime) {
            let pool = [
                sim.time,
                sim.time + 0.1,
                sim.time * 0.5,
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
        };
        let vr = self.vr_of(&v);
        let e = sim.set(v.as_ref(), Type::Real, x.is_finite());
        // SAFETY: one reference and one value.
        let r = unsafe { (self.u.api.fmi2SetReal)(s.c, &vr, 1, &x) };
        self.expect(s, &format!("fmi2SetReal({vr}, {x})"), sim, e, r, seen)?;
        if e == Expect::Ok && v.as_ref().is_some_and(|v| v.key == Key::MeasTime) {
            sim.meas_time = x;
        }
        Ok(())
    }

    pub(super) fn set_boolean(&mut self, s: &Slave, sim: &mut Sim, seen: usize) -> Result<()> {
        let epoch = self
            .key_vr(Key::MeasEpoch)
            .filter(|_| self.rng.random_bool(0.4));
        let v = match epoch {
            Some(vr) => self.vars.get(vr as usize).cloned(),
            None => self.var(Some(Type::Boolean)),
        };
        let b = self.rng.random_bool(0.5);
        let vr = self.vr_of(&v);
        let e = sim.set(v.as_ref(), Type::Boolean, true);
        // SAFETY: one reference and one value.
        let r = unsafe { (self.u.api.fmi2SetBoolean)(s.c, &vr, 1, &(b as c_int)) };
        self.expect(s, "fmi2SetBoolean", sim, e, r, seen)?;
        if e == Expect::Ok
            && let Some(v) = &v
        {
            match v.key {
                Key::MeasEpoch => sim.meas_epoch = b,
                Key::Dispersed | Key::AllowExternalFiles => sim.engine = false,
                _ => {}
            }
        }
        Ok(())
    }

    /// Set `scenario`, `filter` or `seed` to a valid, invalid or over-long value.
    pub(super) fn set_param(&mut self, s: &Slave, sim: &mut Sim, seen: usize) -> Result<()> {
        let u = self.u;
        let api = &u.api;
        let which = self.rng.random_range(0..3);
        if which == 2 {
            let x = SEEDS[self.rng.random_range(0..SEEDS.len())];
            let v = self.vars.iter().find(|v| v.key == Key::Seed).cloned();
            let vr = self.vr_of(&v);
            let e = sim.set(v.as_ref(), Type::Integer, x >= 0);
            // SAFETY: one reference and one value.
            let r = unsafe { (api.fmi2SetInteger)(s.c, &vr, 1, &x) };
            self.expect(s, "fmi2SetInteger(seed)", sim, e, r, seen)?;
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
        let value: String = match (key, self.rng.random_range(0..10)) {
            (_, 0) => "a".repeat(MAX_STRING_BYTES + 1),
            (_, 1) => String::new(),
            (Key::Scenario, 2..=4) => {
                BAD_SCENARIOS[self.rng.random_range(0..BAD_SCENARIOS.len())].into()
            }
            (Key::Scenario, _) => {
                BUILTIN_NAMES[self.rng.random_range(0..BUILTIN_NAMES.len())].into()
            }
            (_, 2) => BAD_FILTERS[self.rng.random_range(0..BAD_FILTERS.len())].into(),
            _ => {
                let all = entrynav::estimation::nav::FilterKind::ALL;
                all[self.rng.random_range(0..all.len())].name().into()
            }
        };
        if value.len() > MAX_STRING_BYTES {
            self.stats.over_bound += 1;
        }
        let v = self.vars.iter().find(|v| v.key == key).cloned();
        let vr = self.vr_of(&v);
        let known_filter = entrynav::estimation::nav::FilterKind::parse(&value).is_ok();
        let valid = value.len() <= MAX_STRING_BYTES
            && !value.trim().is_empty()
            && (key == Key::Scenario || known_filter);
        let e = sim.set(v.as_ref(), Type::String, valid);
        let c = CString::new(value.clone())?;
        // SAFETY: one reference and one C string.
        let r = unsafe { (api.fmi2SetString)(s.c, &vr, 1, &c.as_ptr()) };
        self.expect(s, "fmi2SetString", sim, e, r, seen)?;
        if e == Expect::Ok {
            let field = if key == Key::Scenario {
                &mut sim.scenario
            } else {
                &mut sim.filter
            };
            if *field != value {
                *field = value.trim().to_string();
                sim.engine = false;
            }
        }
        Ok(())
    }
}
