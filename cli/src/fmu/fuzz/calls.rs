//! The fuzzer's FMU-state, status, logging, bound and instantiation calls (see [`super::ops`]).

use super::model::{Expect, Sim, status_query};
use super::ops::{State, same_or_close};
use super::*;
use entrynav_fmu::limits::{
    MAX_CATEGORIES, MAX_SNAPSHOTS, MAX_STATE_BYTES, MAX_STRING_BYTES, MAX_STRING_REFS,
    MAX_VALUE_REFS,
};
use std::ffi::{CString, c_char, c_int};

impl Fuzzer<'_> {
    pub(super) fn get_state(
        &mut self,
        s: &Slave,
        sim: &mut Sim,
        saved: &mut Vec<(State, Sim)>,
        seen: usize,
    ) -> Result<()> {
        let overwrite = !saved.is_empty() && self.rng.random_bool(0.3);
        let mut p: State = if overwrite {
            saved[0].0
        } else {
            std::ptr::null_mut()
        };
        // SAFETY: our instance; *p is null or a state it handed out.
        let r = unsafe { (self.u.api.fmi2GetFMUstate)(s.c, &mut p) };
        let e = if overwrite || saved.len() < MAX_SNAPSHOTS {
            Expect::Ok
        } else {
            Expect::Refused
        };
        self.expect(s, "fmi2GetFMUstate", sim, e, r, seen)?;
        if r == 0 {
            if overwrite {
                saved[0].1 = sim.clone();
            } else {
                saved.push((p, sim.clone()));
            }
        }
        Ok(())
    }

    /// Serialise a held state, then deserialise it unchanged, corrupted, cut short, or with a
    /// size over the bound.
    pub(super) fn serialize(
        &mut self,
        s: &Slave,
        sim: &mut Sim,
        saved: &mut Vec<(State, Sim)>,
        seen: usize,
    ) -> Result<()> {
        let u = self.u;
        let api = &u.api;
        let Some(&(p, ref ps)) = saved.last() else {
            return Ok(());
        };
        let ps = ps.clone();
        let mut size = 0usize;
        // SAFETY: our instance and state.
        let r = unsafe { (api.fmi2SerializedFMUstateSize)(s.c, p, &mut size) };
        self.expect(s, "fmi2SerializedFMUstateSize", sim, Expect::Ok, r, seen)?;
        let mut buf = vec![0u8; size];
        // SAFETY: a buffer of `size` bytes (and a claim one byte short, refused).
        let (r, short) = unsafe {
            (
                (api.fmi2SerializeFMUstate)(s.c, p, buf.as_mut_ptr(), size),
                (api.fmi2SerializeFMUstate)(s.c, p, buf.as_mut_ptr(), size.saturating_sub(1)),
            )
        };
        self.expect(s, "fmi2SerializeFMUstate", sim, Expect::Ok, r, seen)?;
        self.expect(
            s,
            "fmi2SerializeFMUstate (short buffer)",
            sim,
            Expect::Refused,
            short,
            seen,
        )?;
        let room = saved.len() < MAX_SNAPSHOTS;
        let (bytes, len, e) = match self.rng.random_range(0..4) {
            0 if !buf.is_empty() => {
                let i = self.rng.random_range(0..buf.len());
                buf[i] ^= 1 << self.rng.random_range(0..8);
                (buf.as_ptr(), buf.len(), Expect::Refused)
            }
            1 => (buf.as_ptr(), buf.len() / 2, Expect::Refused),
            2 => {
                self.stats.over_bound += 1;
                // A size over the bound with a small buffer: refused before anything is read.
                (buf.as_ptr(), MAX_STATE_BYTES + 1, Expect::Refused)
            }
            _ => (
                buf.as_ptr(),
                buf.len(),
                if room { Expect::Ok } else { Expect::Refused },
            ),
        };
        let mut q: State = std::ptr::null_mut();
        // SAFETY: `len` readable bytes, except the over-the-bound claim, which is never read.
        let r = unsafe { (api.fmi2DeSerializeFMUstate)(s.c, bytes, len, &mut q) };
        self.expect(s, "fmi2DeSerializeFMUstate", sim, e, r, seen)?;
        if r == 0 {
            saved.push((q, ps));
        }
        Ok(())
    }

    pub(super) fn status(&mut self, s: &Slave, sim: &mut Sim, seen: usize) -> Result<()> {
        let u = self.u;
        let api = &u.api;
        let function = self.rng.random_range(0..5usize);
        let kind = [-1, 0, 1, 2, 3, 4, 99][self.rng.random_range(0..7)];
        let e = status_query(sim.st, function, kind);
        let (mut st, mut x, mut i, mut b, mut p) =
            (0 as c_int, 0.0, 0 as c_int, 0 as c_int, std::ptr::null());
        // SAFETY: our instance and one value of the function's type.
        let r = unsafe {
            match function {
                0 => (api.fmi2GetStatus)(s.c, kind, &mut st),
                1 => (api.fmi2GetRealStatus)(s.c, kind, &mut x),
                2 => (api.fmi2GetIntegerStatus)(s.c, kind, &mut i),
                3 => (api.fmi2GetBooleanStatus)(s.c, kind, &mut b),
                _ => (api.fmi2GetStringStatus)(s.c, kind, &mut p),
            }
        };
        self.expect(
            s,
            &format!("Get*Status #{function} kind {kind}"),
            sim,
            e,
            r,
            seen,
        )?;
        if function == 1 && r == 0 {
            ensure!(
                same_or_close(x, sim.time),
                "fmi2LastSuccessfulTime {x}, expected {}",
                sim.time
            );
        }
        Ok(())
    }

    pub(super) fn debug_logging(&mut self, s: &Slave, sim: &mut Sim, seen: usize) -> Result<()> {
        let names: Vec<String> = match self.rng.random_range(0..6) {
            0 => vec![],
            1 => vec!["logAll".into()],
            2 => vec!["logEvents".into(), "logStatusError".into()],
            3 => vec!["logNothing".into()],
            4 => vec!["logAll".repeat(MAX_STRING_BYTES)],
            _ => vec!["logAll".into(); MAX_CATEGORIES + 1],
        };
        let known = entrynav_fmu::xml::LOG_CATEGORIES.map(|c| c.0);
        let valid =
            names.len() <= MAX_CATEGORIES && names.iter().all(|n| known.contains(&n.as_str()));
        if names.len() > MAX_CATEGORIES || names.iter().any(|n| n.len() > MAX_STRING_BYTES) {
            self.stats.over_bound += 1;
        }
        let cs: Vec<CString> = names
            .iter()
            .map(|n| CString::new(n.as_str()))
            .collect::<Result<_, _>>()?;
        let ptrs: Vec<*const c_char> = cs.iter().map(|c| c.as_ptr()).collect();
        // SAFETY: our instance and `ptrs.len()` C strings.
        let r = unsafe { (self.u.api.fmi2SetDebugLogging)(s.c, 1, ptrs.len(), ptrs.as_ptr()) };
        self.expect(
            s,
            "fmi2SetDebugLogging",
            sim,
            if valid { Expect::Ok } else { Expect::Refused },
            r,
            seen,
        )
    }

    /// Counts and sizes past their bounds: each must be refused without being read.
    pub(super) fn over_bound(&mut self, s: &Slave, sim: &mut Sim, seen: usize) -> Result<()> {
        let u = self.u;
        let api = &u.api;
        self.stats.over_bound += 1;
        let n = MAX_VALUE_REFS + 1;
        let mut strings = vec![std::ptr::null::<c_char>(); MAX_STRING_REFS + 1];
        // SAFETY: buffers of MAX_VALUE_REFS + 1 (MAX_STRING_REFS + 1) elements; the counts over
        // the bound are refused unread.
        let r = unsafe {
            match self.rng.random_range(0..4) {
                0 => (api.fmi2GetReal)(s.c, self.big_vr.as_ptr(), n, self.big_out.as_mut_ptr()),
                1 => (api.fmi2SetReal)(s.c, self.big_vr.as_ptr(), n, self.big_out.as_ptr()),
                2 => (api.fmi2GetString)(
                    s.c,
                    self.big_vr.as_ptr(),
                    MAX_STRING_REFS + 1,
                    strings.as_mut_ptr(),
                ),
                _ => (api.fmi2GetReal)(
                    s.c,
                    self.big_vr.as_ptr(),
                    usize::MAX / 16,
                    self.big_out.as_mut_ptr(),
                ),
            }
        };
        self.expect(
            s,
            "fmi2Get/SetReal over MAX_VALUE_REFS",
            sim,
            Expect::Refused,
            r,
            seen,
        )
    }

    /// fmi2Instantiate with another model's GUID (refused by a bound library), an over-long GUID
    /// or name (refused), or the right GUID (accepted).
    pub(super) fn instantiate_variants(&mut self) -> Result<()> {
        let u = self.u;
        let other = Model::ALL
            .into_iter()
            .find(|m| m.identifier() != u.spec.identifier())
            .map(entrynav_fmu::guid_of)
            .unwrap_or_default();
        let (name, guid, ok) = match self.rng.random_range(0..4) {
            0 => (
                "x".to_string(),
                other,
                u.binding.is_none() && u.spec.specific().is_none(),
            ),
            1 => ("x".to_string(), "{".repeat(300), false),
            2 => ("n".repeat(MAX_STRING_BYTES + 1), self.guid.clone(), false),
            _ => ("ok".to_string(), self.guid.clone(), true),
        };
        self.stats.calls += 1;
        match Slave::new(u, &name, &guid, &self.uri) {
            Ok(_slave) => ensure!(ok, "fmi2Instantiate accepted {name:.20} / {guid:.60}"),
            Err(HostError::Instantiate(msgs)) => {
                ensure!(!ok, "fmi2Instantiate refused {guid}: {msgs:?}");
                ensure!(
                    msgs.iter().any(|(st, m)| *st == 3 && !m.is_empty()),
                    "no reason logged"
                );
                if guid.len() > 256 || name.len() > MAX_STRING_BYTES {
                    self.stats.over_bound += 1;
                }
            }
            Err(e) => return Err(e.into()),
        }
        Ok(())
    }
}
