//! The fuzzer's FMU-state calls: get, set, free, serialise and deserialise, with null, foreign,
//! corrupted, truncated and over-long states, and every state that deserialises serialised again
//! to the same bytes.

use super::fuzzer::{Fuzzer, Saved, Version};
use super::model::{Expect, Sim, St};
use anyhow::{Result, ensure};
use entrynav_fmi_host::{FmiInstance, FmuState};
use entrynav_fmu::limits::{MAX_SNAPSHOTS, MAX_STATE_BYTES};
use rand::RngExt;

impl<V: Version> Fuzzer<V> {
    /// GetFMUState into a new state, over a held one, or into a foreign pointer (refused).
    pub(super) fn get_state(
        &mut self,
        s: &V::Instance,
        sim: &mut Sim,
        saved: &mut Saved,
    ) -> Result<()> {
        let mut local = 0u64;
        let (mut p, e, what) = match self.rng.random_range(0..10) {
            0..=2 if !saved.is_empty() => (saved[0].0, Expect::Ok, "GetFMUState (overwrite)"),
            3 => (
                &mut local as *mut u64 as FmuState,
                Expect::Refused,
                "GetFMUState (foreign *FMUState)",
            ),
            _ => (
                std::ptr::null_mut(),
                Expect::ok_if(saved.len() < MAX_SNAPSHOTS),
                "GetFMUState",
            ),
        };
        let before = p;
        // SAFETY: our instance; *p is null, a state it handed out, or a foreign pointer that must
        // be refused unread.
        let r = unsafe { s.get_fmu_state(&mut p) };
        self.expect(s, what, sim, e, r)?;
        if r != 0 {
            ensure!(p == before, "{what} answered {r} and changed *FMUState");
        } else if before.is_null() {
            ensure!(!p.is_null(), "{what} answered OK and left *FMUState NULL");
            saved.push((p, sim.clone()));
        } else {
            ensure!(p == before, "{what} (overwrite) moved the state");
            saved[0].1 = sim.clone();
        }
        Ok(())
    }

    /// SetFMUState of a held state (the model goes back to it) or of a foreign pointer.
    pub(super) fn set_state(
        &mut self,
        s: &V::Instance,
        sim: &mut Sim,
        saved: &mut [(FmuState, Sim)],
    ) -> Result<()> {
        if saved.is_empty() || self.rng.random_bool(0.1) {
            let mut local = 0u64;
            let p = if self.rng.random_bool(0.5) {
                std::ptr::null_mut()
            } else {
                &mut local as *mut u64 as FmuState
            };
            // SAFETY: a null or foreign pointer must be refused unread.
            let r = unsafe { s.set_fmu_state(p) };
            return self.expect(s, "SetFMUState (null or foreign)", sim, Expect::Refused, r);
        }
        let i = self.rng.random_range(0..saved.len());
        // SAFETY: our instance and a state it handed out.
        let r = unsafe { s.set_fmu_state(saved[i].0) };
        self.expect(s, "SetFMUState", sim, Expect::Ok, r)?;
        *sim = saved[i].1.clone();
        sim.engine = matches!(sim.st, St::Step | St::Terminated) || sim.stepped;
        Ok(())
    }

    /// FreeFMUState of a held state (the pointer is set to NULL), of a NULL state (a no-op)
    /// or of a foreign one (refused).
    pub(super) fn free_state(
        &mut self,
        s: &V::Instance,
        sim: &mut Sim,
        saved: &mut Saved,
    ) -> Result<()> {
        let mut local = 0u64;
        let (mut p, e, held) = match self.rng.random_range(0..6) {
            0 => (std::ptr::null_mut(), Expect::Ok, false),
            1 => (&mut local as *mut u64 as FmuState, Expect::Refused, false),
            _ if !saved.is_empty() => {
                let i = self.rng.random_range(0..saved.len());
                (saved.swap_remove(i).0, Expect::Ok, true)
            }
            _ => return Ok(()),
        };
        let foreign = p;
        // SAFETY: our instance; a state it handed out, null, or a foreign pointer refused unread.
        let r = unsafe { s.free_fmu_state(&mut p) };
        self.expect(s, "FreeFMUState", sim, e, r)?;
        ensure!(
            if held { p.is_null() } else { p == foreign },
            "FreeFMUState answered {r} and left *FMUState {p:?}"
        );
        Ok(())
    }

    /// Serialise a held state (and into a buffer one byte short: refused), then deserialise it
    /// unchanged (and serialise that again: the same bytes), corrupted, cut short, empty, or with
    /// a size over the bound.
    pub(super) fn serialize(
        &mut self,
        s: &V::Instance,
        sim: &mut Sim,
        saved: &mut Saved,
    ) -> Result<()> {
        if saved.is_empty() {
            self.get_state(s, sim, saved)?;
        }
        let Some((p, ps)) = saved.last().cloned() else {
            return Ok(());
        };
        let mut size = usize::MAX;
        // SAFETY: our instance and state.
        let r = unsafe { s.serialized_fmu_state_size(p, &mut size) };
        self.expect(s, "SerializedFMUStateSize", sim, Expect::Ok, r)?;
        ensure!(
            size > 0 && size <= MAX_STATE_BYTES,
            "a serialised state of {size} bytes"
        );
        let mut buf = vec![0u8; size];
        // SAFETY: a buffer of `size` bytes.
        let r = unsafe { s.serialize_fmu_state(p, buf.as_mut_ptr(), size) };
        self.expect(s, "SerializeFMUState", sim, Expect::Ok, r)?;
        // SAFETY: a buffer one byte shorter than the state: refused before it is written.
        let r = unsafe { s.serialize_fmu_state(p, buf.as_mut_ptr(), size - 1) };
        self.expect(
            s,
            "SerializeFMUState (short buffer)",
            sim,
            Expect::Refused,
            r,
        )?;
        let room = saved.len() < MAX_SNAPSHOTS;
        let mut bad = buf.clone();
        let (len, e, what) = match self.rng.random_range(0..6) {
            0 => {
                let i = self.rng.random_range(0..bad.len());
                bad[i] ^= 1 << self.rng.random_range(0..8);
                (bad.len(), Expect::Refused, "corrupted")
            }
            1 => (bad.len() / 2, Expect::Refused, "cut in half"),
            2 => (bad.len() - 1, Expect::Refused, "one byte short"),
            3 => {
                self.stats.over_bound += 1;
                // A size over the bound with a small buffer: refused before anything is read.
                (MAX_STATE_BYTES + 1, Expect::Refused, "over the bound")
            }
            _ => (bad.len(), Expect::ok_if(room), "intact"),
        };
        let mut q: FmuState = std::ptr::null_mut();
        // SAFETY: `len` readable bytes, except the over-the-bound claim, which is never read.
        let r = unsafe { s.deserialize_fmu_state(bad.as_ptr(), len, &mut q) };
        self.expect(s, &format!("DeserializeFMUState ({what})"), sim, e, r)?;
        if r != 0 {
            ensure!(q.is_null(), "a refused DeserializeFMUState wrote a state");
            return Ok(());
        }
        saved.push((q, ps));
        // Serialised again, the state gives the same bytes.
        let mut again = vec![0u8; size + 1];
        let mut size2 = 0usize;
        // SAFETY: our instance and state.
        let r = unsafe { s.serialized_fmu_state_size(q, &mut size2) };
        self.expect(
            s,
            "SerializedFMUStateSize of a deserialised state",
            sim,
            Expect::Ok,
            r,
        )?;
        // SAFETY: a buffer one byte longer than the state.
        let r = unsafe { s.serialize_fmu_state(q, again.as_mut_ptr(), size + 1) };
        self.expect(
            s,
            "SerializeFMUState of a deserialised state",
            sim,
            Expect::Ok,
            r,
        )?;
        ensure!(
            size2 == size && again[..size] == buf[..],
            "a deserialised FMU state serialises to other bytes ({size2} bytes, was {size})"
        );
        self.stats.round_trips += 1;
        Ok(())
    }
}
