//! The fuzzer's logging and bound calls: SetDebugLogging with no, known, unknown, over-long, too
//! many or null categories; counts and sizes past their bounds (refused unread) and exactly at
//! them (accepted); null arrays with and without a count.

use super::fuzzer::{Fuzzer, Version};
use super::model::{Expect, Sim};
use super::variables::What;
use anyhow::Result;
use entrynav_fmi_host::FmiInstance;
use entrynav_fmu::instance::Type3;
use entrynav_fmu::limits::{MAX_CATEGORIES, MAX_STRING_BYTES, MAX_STRING_REFS, MAX_VALUE_REFS};
use entrynav_fmu::vars::Causality;
use entrynav_fmu::xml::LOG_CATEGORIES;
use rand::RngExt;
use std::ffi::{CString, c_char};

impl<V: Version> Fuzzer<V> {
    /// SetDebugLogging with no, known, unknown, over-long, too many or null categories.
    pub(super) fn debug_logging(&mut self, s: &V::Instance, sim: &mut Sim) -> Result<()> {
        let names: Vec<String> = match self.rng.random_range(0..7) {
            0 => vec![],
            1 => vec!["logAll".into()],
            2 => vec!["logEvents".into(), "logStatusError".into()],
            3 => vec!["logNothing".into()],
            4 => vec!["logAll".repeat(MAX_STRING_BYTES)],
            5 => vec!["logAll".into(); MAX_CATEGORIES + 1],
            _ => {
                // SAFETY: a null array with a non-zero count must be refused unread.
                let r = unsafe { s.set_debug_logging(1.into(), 2, std::ptr::null()) };
                self.stats.null_arrays += 1;
                return self.expect(
                    s,
                    "SetDebugLogging(NULL categories)",
                    sim,
                    Expect::Refused,
                    r,
                );
            }
        };
        let known = LOG_CATEGORIES.map(|c| c.0);
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
        let on = [0u8, 1, 1, 2][self.rng.random_range(0..4)];
        // SAFETY: our instance and `ptrs.len()` C strings.
        let r = unsafe { s.set_debug_logging(on.into(), ptrs.len(), ptrs.as_ptr()) };
        self.expect(s, "SetDebugLogging", sim, Expect::ok_if(valid), r)
    }

    /// A read of exactly MAX_VALUE_REFS references (copies of one Float64 input or parameter):
    /// accepted where reads are.
    fn at_the_bound(&mut self, s: &V::Instance, sim: &mut Sim) -> Result<()> {
        let Some(v) = self
            .variables
            .iter()
            .find(|v| {
                v.ty == Type3::Float64
                    && matches!(v.what, What::Scalar(i) if self.vars[i].causality != Causality::Output)
            })
            .copied()
        else {
            return Ok(());
        };
        let vrs = vec![v.vr; MAX_VALUE_REFS];
        // SAFETY: MAX_VALUE_REFS references and values.
        let r = unsafe {
            s.get_float64(
                vrs.as_ptr(),
                vrs.len(),
                self.big_out.as_mut_ptr(),
                vrs.len(),
            )
        };
        self.expect(
            s,
            "GetFloat64 of MAX_VALUE_REFS references",
            sim,
            Expect::ok_if(sim.st.readable()),
            r,
        )
    }

    /// Counts and sizes past their bounds (refused unread), and a read of exactly
    /// MAX_VALUE_REFS references.
    pub(super) fn over_bound(&mut self, s: &V::Instance, sim: &mut Sim) -> Result<()> {
        let which = self.rng.random_range(0..6);
        if which == 5 {
            return self.at_the_bound(s, sim);
        }
        self.stats.over_bound += 1;
        let n = MAX_VALUE_REFS + 1;
        let (ns, huge) = (MAX_STRING_REFS + 1, usize::MAX / 16);
        let mut strings = vec![std::ptr::null::<c_char>(); ns];
        let (vr, out) = (self.big_vr.as_ptr(), self.big_out.as_mut_ptr());
        // SAFETY: buffers of MAX_VALUE_REFS + 1 (MAX_STRING_REFS + 1) elements; the counts over
        // the bound are refused unread.
        let r = unsafe {
            match which {
                0 => s.get_float64(vr, n, out, n),
                1 => s.set_float64(vr, n, out, n),
                2 => s.get_string(vr, ns, strings.as_mut_ptr(), ns),
                3 => s.set_string(vr, ns, strings.as_ptr(), ns),
                _ => s.get_float64(vr, huge, out, huge),
            }
        };
        self.expect(
            s,
            &format!("count over its bound #{which}"),
            sim,
            Expect::Refused,
            r,
        )
    }

    /// Null arrays: with a non-zero count they are refused unread; with zero counts the call is
    /// the empty read or write (allowed where the function is).
    pub(super) fn null_arrays(&mut self, s: &V::Instance, sim: &mut Sim) -> Result<()> {
        let Some(v) = self.var(Some(Type3::Float64)) else {
            return Ok(());
        };
        let (null, nothing) = (std::ptr::null::<u32>(), std::ptr::null::<f64>());
        let mut x = vec![0.0; v.len];
        self.stats.null_arrays += 1;
        // SAFETY: every non-null array has `v.len` elements (one reference holds them); null ones
        // go with the counts.
        let (what, r, e) = unsafe {
            match self.rng.random_range(0..5) {
                0 => (
                    "GetFloat64(NULL references)",
                    s.get_float64(null, 1, x.as_mut_ptr(), v.len),
                    Expect::Refused,
                ),
                1 => (
                    "GetFloat64(NULL values)",
                    s.get_float64(&v.vr, 1, std::ptr::null_mut(), v.len),
                    Expect::Refused,
                ),
                2 => (
                    "SetFloat64(NULL values)",
                    s.set_float64(&v.vr, 1, nothing, v.len),
                    Expect::Refused,
                ),
                3 => (
                    "GetFloat64(nothing, NULL arrays)",
                    s.get_float64(null, 0, std::ptr::null_mut(), 0),
                    Expect::ok_if(sim.st.readable()),
                ),
                _ => (
                    "SetFloat64(nothing, NULL arrays)",
                    s.set_float64(null, 0, nothing, 0),
                    Expect::ok_if(sim.st.writable()),
                ),
            }
        };
        self.expect(s, what, sim, e, r)
    }
}
