//! A random call sequence on a fresh instance, its FMU states and the instance freed, and the
//! calls a freed and a null instance must refuse.

use super::fuzzer::{Fuzzer, Saved, Version};
use super::model::Expect;
use anyhow::{Result, ensure};
use entrynav_fmi_host::FmiInstance;
use rand::RngExt;

impl<V: Version> Fuzzer<V> {
    /// One random call sequence of `len` calls on a fresh instance, then its states freed (or
    /// left to the instance's free) and the instance freed.
    pub(super) fn sequence(&mut self, len: usize) -> Result<()> {
        let name = format!("fuzz{}", self.stats.sequences);
        let logging_on = self.rng.random_bool(0.5);
        let s = V::instantiate(self, &name, logging_on)?;
        self.stats.calls += 1;
        self.stats.sequences += 1;
        let mut sim = self.fresh();
        let mut saved: Saved = Vec::new();
        for _ in 0..len {
            self.op(&s, &mut sim, &mut saved)?;
        }
        if self.rng.random_bool(0.5) {
            for (mut p, _) in saved {
                // SAFETY: a state the instance handed out.
                let r = unsafe { s.free_fmu_state(&mut p) };
                self.expect(&s, "FreeFMUState", &sim, Expect::Ok, r)?;
                ensure!(p.is_null(), "FreeFMUState left the pointer set");
            }
        }
        self.free(s)
    }

    /// Free the instance, then (sometimes) call it: refused, nothing written, nothing logged.
    pub(super) fn free(&mut self, mut s: V::Instance) -> Result<()> {
        s.free();
        self.stats.calls += 1;
        if self.rng.random_bool(0.2) {
            let step = s.do_step(0.0, 1.0, false, true);
            let r = [step.status, s.reset(), s.exit_initialization_mode()];
            // Freeing it again is a no-op.
            s.free();
            self.stats.calls += 4;
            self.stats.dead_calls += 4;
            self.stats.statuses[3] += 3;
            ensure!(r == [3, 3, 3], "calls on a freed instance answered {r:?}");
            ensure!(
                step.flags.is_none_or(|f| f == [0xAA; 3])
                    && step.last_successful_time.is_none_or(f64::is_nan),
                "DoStep on a freed instance wrote its outputs"
            );
            let msgs = s.take_messages();
            ensure!(
                msgs.is_empty(),
                "a freed instance logged through its callback: {msgs:?}"
            );
        }
        Ok(())
    }

    /// A null instance is refused by every function (and freed without harm).
    pub(super) fn null_instance(&mut self) -> Result<()> {
        let mut s = self.version.null_instance();
        let (vr, mut x, mut p) = (0u32, 0.0, std::ptr::null_mut());
        s.free();
        let step = s.do_step(0.0, 1.0, false, false);
        let mut r = vec![
            step.status,
            s.terminate(),
            s.reset(),
            s.enter_initialization_mode(None, 0.0, None),
        ];
        // SAFETY: a null instance must refuse every call without using its arguments.
        unsafe {
            r.push(s.get_float64(&vr, 1, &mut x, 1));
            r.push(s.set_debug_logging(1.into(), 0, std::ptr::null()));
            r.push(s.get_fmu_state(&mut p));
        }
        r.extend(V::null_calls(&s));
        self.stats.calls += r.len() + 1;
        self.stats.dead_calls += r.len() + 1;
        self.stats.statuses[3] += r.len();
        ensure!(
            r.iter().all(|&s| s == 3),
            "a null instance was answered {r:?}"
        );
        ensure!(p.is_null(), "GetFMUState of a null instance wrote a state");
        Ok(())
    }
}
