//! The fuzzer's calls: one random call (or a short group, such as a serialisation round trip)
//! per [`Fuzzer::op`], with its expected answer from the model. The lifecycle and step calls
//! are here; reads in [`super::values`], writes in [`super::setters`], FMU states in
//! [`super::state`], logging and bounds in [`super::bounds`], and the calls only one version has
//! in its own module.

use super::fuzzer::{Fuzzer, Saved, Version};
use super::model::{Expect, Sim, St, same_time};
use super::vals::Vals;
use anyhow::{Result, ensure};
use entrynav_fmi_host::FmiInstance;
use entrynav_fmu::vars::{Key, Model};
use rand::RngExt;

/// Step sizes: ordinary, tiny (down to the smallest denormal), huge (up to f64::MAX; an accepted
/// one runs the scenario to its end, which is most of the fuzzer's time on the combined model, so
/// they are drawn less often than the others) and invalid.
const ORDINARY: [f64; 5] = [1.0, 0.5, 0.1, 2.0, 10.0];
const TINY: [f64; 4] = [1e-3, 1e-9, 1e-300, 5e-324];
const HUGE: [f64; 5] = [1e3, 1e9, 1e18, 1e300, f64::MAX];
const INVALID: [f64; 6] = [0.0, -1.0, -0.0, f64::NAN, f64::INFINITY, f64::NEG_INFINITY];

/// The calls both versions have ([`Fuzzer::op`] `0..SHARED_OPS`); the version's own follow.
const SHARED_OPS: u32 = 27;

impl<V: Version> Fuzzer<V> {
    /// One random call (or group of calls).
    pub(super) fn op(&mut self, s: &V::Instance, sim: &mut Sim, saved: &mut Saved) -> Result<()> {
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
            self.rng.random_range(0..SHARED_OPS + V::SPECIAL_OPS)
        };
        match pick {
            0 => V::initialise(self, s, sim)?,
            1 => self.exit_init(s, sim)?,
            2..=7 => self.do_step(s, sim)?,
            8 => self.terminate(s, sim)?,
            9 => self.reset(s, sim)?,
            10..=13 => self.get(s, sim)?,
            14..=16 => self.set_float64(s, sim)?,
            17 => self.set_boolean(s, sim)?,
            18 => self.set_param(s, sim)?,
            19 => self.set_int32(s, sim)?,
            20 => self.get_state(s, sim, saved)?,
            21 => self.set_state(s, sim, saved)?,
            22 => self.serialize(s, sim, saved)?,
            23 => self.free_state(s, sim, saved)?,
            24 => self.debug_logging(s, sim)?,
            25 => self.over_bound(s, sim)?,
            26 => self.null_arrays(s, sim)?,
            k => V::special(self, k - SHARED_OPS, s, sim, saved)?,
        }
        Ok(())
    }

    /// Leave Initialization Mode: an engine is built from the parameters, or the instance fails.
    fn exit_init(&mut self, s: &V::Instance, sim: &mut Sim) -> Result<()> {
        let r = s.exit_initialization_mode();
        let e = match (sim.st, sim.params_ok(&self.sc, self.model)) {
            (St::Init, true) => Expect::Ok,
            (St::Init, false) => Expect::Fails,
            _ => Expect::Refused,
        };
        self.expect(s, "ExitInitializationMode", sim, e, r)?;
        match e {
            Expect::Ok => (sim.st, sim.engine) = (St::Step, true),
            Expect::Fails => sim.st = St::Error,
            _ => {}
        }
        Ok(())
    }

    fn terminate(&mut self, s: &V::Instance, sim: &mut Sim) -> Result<()> {
        let r = s.terminate();
        let legal = sim.st == St::Step;
        self.expect(s, "Terminate", sim, Expect::ok_if(legal), r)?;
        if legal {
            sim.st = St::Terminated;
        }
        Ok(())
    }

    fn reset(&mut self, s: &V::Instance, sim: &mut Sim) -> Result<()> {
        let r = s.reset();
        self.expect(s, "Reset", sim, Expect::Ok, r)?;
        *sim = self.fresh();
        Ok(())
    }

    /// The filter FMU's last processed epoch (nav_time, nav_status == failed), read through the
    /// API as a master would (nav_status is an Enumeration: Int32 in FMI 2.0, Int64 in 3.0).
    fn read_nav(&mut self, s: &V::Instance, sim: &Sim) -> Result<Option<(f64, bool)>> {
        if self.model != Model::Filter || sim.st != St::Step {
            return Ok(None);
        }
        let (Some(tv), Some(sv)) = (self.key_var(Key::NavTime), self.key_var(Key::NavStatus))
        else {
            return Ok(None);
        };
        // SAFETY: one reference and room for one value each.
        let ((r1, time), (r2, status)) = unsafe {
            (
                self.get_raw(s, tv.ty, (&tv.vr, 1), 1, false, 1)?,
                self.get_raw(s, sv.ty, (&sv.vr, 1), 1, false, 1)?,
            )
        };
        for r in [r1, r2] {
            self.expect(s, "Get(nav_time, nav_status)", sim, Expect::Ok, r)?;
        }
        let (Vals::F64(time), Some(status)) = (time, status.integer(0)) else {
            anyhow::bail!("nav_time or nav_status is not of the type it is read as");
        };
        ensure!((0..=2).contains(&status), "nav_status = {status}");
        Ok(Some((time[0], status == 2)))
    }

    /// A step from the current time (or now and then another) of an ordinary, tiny, huge or
    /// invalid size; FMI 3.0's output flags and lastSuccessfulTime checked.
    fn do_step(&mut self, s: &V::Instance, sim: &mut Sim) -> Result<()> {
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
        let e = sim.do_step(&self.sc, self.model, t, h, nav);
        if e == Expect::Refused && sim.do_step(&self.sc, self.model, t, h, None) != e {
            self.stats.work_refused += 1;
        }
        // Now and then the output flags are not asked for (null pointers, which FMI 3.0 allows).
        let flags = !self.rng.random_bool(0.05);
        let no_prior = self.rng.random_bool(0.5);
        let a = s.do_step(t, h, no_prior, flags);
        self.expect(s, &format!("DoStep({t}, {h})"), sim, e, a.status)?;
        if let Some(f) = a.flags {
            ensure!(
                f == [0, 0, 0],
                "DoStep({t}, {h}) answered {} with eventHandlingNeeded, terminateSimulation, earlyReturn {f:?} (expected all false)",
                a.status
            );
        }
        let expected = match (e, sim.st) {
            (Expect::OkOrWarning, _) => Some(t + h),
            (_, St::Instantiated | St::Init) => Some(0.0),
            (_, St::Step | St::Terminated) => Some(sim.time),
            (_, St::Error) => None,
        };
        if let (Some(last), Some(x)) = (a.last_successful_time, expected) {
            ensure!(
                same_time(last, x),
                "DoStep({t}, {h}) in state {:?} answered {} with lastSuccessfulTime {last}, expected {x}",
                sim.st,
                a.status
            );
        }
        if e == Expect::OkOrWarning {
            sim.time = t + h;
            sim.stepped = true;
            self.stats.steps += 1;
            V::after_step(self, s, sim)?;
        }
        Ok(())
    }
}
