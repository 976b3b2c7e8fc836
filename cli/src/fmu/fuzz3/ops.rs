//! The FMI 3.0 fuzzer's calls: one random fmi3 call (or a short group, such as a serialisation
//! round trip) per [`Fuzzer::op`], with its expected answer from the model; the lifecycle and
//! step calls here, reads in [`super::values`], writes in [`super::setters`], FMU states in
//! [`super::state`], logging, unsupported functions and bounds in [`super::calls`],
//! instantiations in [`super::inst`].

use super::model::{Expect, Sim, St, V3, What, same_time};
use super::*;
use entrynav_fmu::instance::Type3;

/// Step sizes: ordinary, tiny (down to the smallest denormal), huge (up to f64::MAX; an accepted
/// one runs the scenario to its end, which is most of the fuzzer's time on the combined model, so
/// they are drawn less often than the others) and invalid.
const ORDINARY: [f64; 5] = [1.0, 0.5, 0.1, 2.0, 10.0];
const TINY: [f64; 4] = [1e-3, 1e-9, 1e-300, 5e-324];
const HUGE: [f64; 5] = [1e3, 1e9, 1e18, 1e300, f64::MAX];
const INVALID: [f64; 6] = [0.0, -1.0, -0.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY];

/// Start times (only 0 is accepted; -0 is 0) and stop times of fmi3EnterInitializationMode.
const STARTS: [f64; 6] = [0.0, 0.0, 0.0, -0.0, 1.0, f64::NAN];
const STOPS: [f64; 8] = [300.0, 1e9, 10.0, 1e-9, 0.0, f64::INFINITY, f64::NAN, -5.0];

impl Fuzzer<'_> {
    /// A variable of type `ty` (any type if `None`), or `None` now and then: an unknown reference.
    pub(super) fn var(&mut self, ty: Option<Type3>) -> Option<V3> {
        if self.rng.random_bool(0.05) {
            return None;
        }
        let n = self
            .v3
            .iter()
            .filter(|v| ty.is_none_or(|t| v.ty == t))
            .count();
        if n == 0 {
            return None;
        }
        let k = self.rng.random_range(0..n);
        self.v3
            .iter()
            .filter(|v| ty.is_none_or(|t| v.ty == t))
            .nth(k)
            .copied()
    }

    /// The reference of `v`, or an unknown one.
    pub(super) fn vr_of(&mut self, v: &Option<V3>) -> u32 {
        match v {
            Some(v) => v.vr,
            None if self.rng.random_bool(0.1) => u32::MAX,
            None => self.v3.len() as u32 + self.rng.random_range(0..1000u32),
        }
    }

    /// The FMI 3.0 variable of table key `key`.
    pub(super) fn key_var(&self, key: Key) -> Option<V3> {
        let i = self.vars.iter().position(|v| v.key == key)?;
        self.v3.get(i).copied()
    }

    /// The FMI 3.0 variable that is `what`.
    pub(super) fn extra(&self, what: What) -> Option<V3> {
        self.v3.iter().find(|v| v.what == what).copied()
    }

    /// One random call (or group of calls).
    pub(super) fn op(
        &mut self,
        s: &Inst,
        sim: &mut Sim,
        saved: &mut Vec<(State3, Sim)>,
    ) -> Result<()> {
        let api = self.api;
        // Half of the calls move the instance on (initialise, step, start again), so sequences
        // spend their time in every state rather than mostly refused.
        let pick = if self.rng.random_bool(0.5) {
            match sim.st {
                St::Instantiated => 0,
                St::Init => 1,
                St::Step if self.rng.random_bool(0.03) => 8,
                St::Step => 2,
                St::Terminated | St::Error => 9,
            }
        } else {
            self.rng.random_range(0..34u32)
        };
        match pick {
            0 => self.enter_init(s, sim)?,
            1 => {
                // SAFETY: our instance.
                let r = unsafe { (api.fmi3ExitInitializationMode)(s.c) };
                let e = match (sim.st, sim.params_ok(&self.sc, self.u.model)) {
                    (St::Init, true) => Expect::Ok,
                    (St::Init, false) => Expect::Fails,
                    _ => Expect::Refused,
                };
                self.expect(s, "fmi3ExitInitializationMode", sim, e, r)?;
                match e {
                    Expect::Ok => (sim.st, sim.engine) = (St::Step, true),
                    Expect::Fails => sim.st = St::Error,
                    _ => {}
                }
            }
            2..=7 => self.do_step(s, sim)?,
            8 => {
                // SAFETY: our instance.
                let r = unsafe { (api.fmi3Terminate)(s.c) };
                let legal = sim.st == St::Step;
                self.expect(s, "fmi3Terminate", sim, Expect::ok_if(legal), r)?;
                if legal {
                    sim.st = St::Terminated;
                }
            }
            9 => {
                // SAFETY: our instance.
                let r = unsafe { (api.fmi3Reset)(s.c) };
                self.expect(s, "fmi3Reset", sim, Expect::Ok, r)?;
                *sim = Sim::new(self.specific());
            }
            10..=13 => self.get(s, sim)?,
            14..=16 => self.set_float64(s, sim)?,
            17 => self.set_boolean(s, sim)?,
            18 => self.set_param(s, sim)?,
            19 => self.set_integer(s, sim)?,
            20 => self.get_state(s, sim, saved)?,
            21 => self.set_state(s, sim, saved)?,
            22 => self.serialize(s, sim, saved)?,
            23 => self.free_state(s, sim, saved)?,
            24 => self.debug_logging(s, sim)?,
            25 | 26 => self.unsupported(s, sim)?,
            27 => self.no_variables(s, sim)?,
            28 => self.over_bound(s, sim)?,
            29 => self.null_arrays(s, sim)?,
            30 | 31 => self.check_arrays(s, sim)?,
            32 => self.get_nvalues(s, sim)?,
            _ => self.instantiate_variants()?,
        }
        Ok(())
    }

    /// fmi3EnterInitializationMode with a start time, and a stop time or none: the experiment
    /// set-up of FMI 2.0 and the entry into Initialization Mode in one call.
    fn enter_init(&mut self, s: &Inst, sim: &mut Sim) -> Result<()> {
        let start = STARTS[self.rng.random_range(0..STARTS.len())];
        let defined = self.rng.random_bool(0.6);
        let stop = STOPS[self.rng.random_range(0..STOPS.len())];
        let tolerance = [1e-6, 0.0, -1.0, f64::NAN][self.rng.random_range(0..4)];
        let tol_defined = self.rng.random_bool(0.5);
        // SAFETY: our instance.
        let r = unsafe {
            (self.api.fmi3EnterInitializationMode)(
                s.c,
                tol_defined as u8,
                tolerance,
                start,
                defined as u8,
                stop,
            )
        };
        let e = sim.enter_init(start, defined.then_some(stop));
        self.expect(
            s,
            &format!("fmi3EnterInitializationMode(start {start}, stop {defined} {stop})"),
            sim,
            e,
            r,
        )?;
        if e == Expect::Ok {
            (sim.st, sim.stop) = (St::Init, defined.then_some(stop));
        }
        Ok(())
    }

    /// The filter FMU's last processed epoch (nav_time, nav_status == failed), read through the
    /// API as a master would: nav_status is an Enumeration, read with fmi3GetInt64.
    fn read_nav(&mut self, s: &Inst, sim: &Sim) -> Result<Option<(f64, bool)>> {
        if self.u.model != Model::Filter || sim.st != St::Step {
            return Ok(None);
        }
        let (Some(tv), Some(sv)) = (self.key_var(Key::NavTime), self.key_var(Key::NavStatus))
        else {
            return Ok(None);
        };
        ensure!(sv.ty == Type3::Int64, "nav_status is not an Int64 variable");
        let (mut last, mut status) = (0.0, 0i64);
        // SAFETY: one reference and one value each.
        let r = unsafe {
            [
                (self.api.fmi3GetFloat64)(s.c, &tv.vr, 1, &mut last, 1),
                (self.api.fmi3GetInt64)(s.c, &sv.vr, 1, &mut status, 1),
            ]
        };
        for r in r {
            self.expect(
                s,
                "fmi3GetFloat64/Int64(nav_time, nav_status)",
                sim,
                Expect::Ok,
                r,
            )?;
        }
        ensure!((0..=2).contains(&status), "nav_status = {status}");
        Ok(Some((last, status == 2)))
    }

    fn do_step(&mut self, s: &Inst, sim: &mut Sim) -> Result<()> {
        let pool: &[f64] = match self.rng.random_range(0..100) {
            0..=2 => &HUGE,
            3..=10 => &TINY,
            11..=22 => &INVALID,
            _ => &ORDINARY,
        };
        let h = pool[self.rng.random_range(0..pool.len())];
        let t = match self.rng.random_range(0..20) {
            0 => sim.time + 0.5,
            1 => sim.time * (1.0 + 1e-6) + 1e-3,
            2 => f64::NAN,
            3 => 1e300,
            _ => sim.time,
        };
        if h >= 1e3 && h.is_finite() {
            self.stats.huge_steps += 1;
        }
        if h > 0.0 && h <= 1e-9 {
            self.stats.tiny_steps += 1;
        }
        let nav = self.read_nav(s, sim)?;
        let e = sim.do_step(&self.sc, self.u.model, t, h, nav);
        if e == Expect::Refused && sim.do_step(&self.sc, self.u.model, t, h, None) != e {
            self.stats.work_refused += 1;
        }
        // The flags start as neither false nor true, the time as NaN: a live instance writes them
        // all (unless the master passed NULL, which this FMU tolerates).
        let (mut event, mut terminate, mut early, mut last) = (0xAAu8, 0xAAu8, 0xAAu8, f64::NAN);
        let null_flags = self.rng.random_bool(0.05);
        let no_prior = self.rng.random_bool(0.5) as u8;
        let flag = |p: &mut u8| -> *mut u8 { if null_flags { std::ptr::null_mut() } else { p } };
        // SAFETY: our instance; each pointer is null or one writable value.
        let r = unsafe {
            (self.api.fmi3DoStep)(
                s.c,
                t,
                h,
                no_prior,
                flag(&mut event),
                flag(&mut terminate),
                flag(&mut early),
                &mut last,
            )
        };
        self.expect(s, &format!("fmi3DoStep({t}, {h})"), sim, e, r)?;
        if !null_flags {
            ensure!(
                (event, terminate, early) == (0, 0, 0),
                "fmi3DoStep({t}, {h}) answered {r} with eventHandlingNeeded {event}, terminateSimulation {terminate}, earlyReturn {early} (expected all false)"
            );
        }
        let expected = match (e, sim.st) {
            (Expect::OkOrWarning, _) => Some(t + h),
            (_, St::Instantiated | St::Init) => Some(0.0),
            (_, St::Step | St::Terminated) => Some(sim.time),
            (_, St::Error) => None,
        };
        if let Some(x) = expected {
            ensure!(
                same_time(last, x),
                "fmi3DoStep({t}, {h}) in state {:?} answered {r} with lastSuccessfulTime {last}, expected {x}",
                sim.st
            );
        }
        if e == Expect::OkOrWarning {
            sim.time = t + h;
            sim.stepped = true;
            self.stats.steps += 1;
            if self.slots > 0 && self.rng.random_bool(0.3) {
                self.check_arrays(s, sim)?;
            }
        }
        Ok(())
    }
}
