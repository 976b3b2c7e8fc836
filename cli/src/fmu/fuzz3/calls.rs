//! The FMI 3.0 fuzzer's other calls: fmi3SetDebugLogging, the functions of capabilities the FMU
//! does not have, the getters and setters of types it has no variables of, and counts past their
//! bounds (see [`super::ops`]).

use super::model::{Expect, Sim};
use super::*;
use entrynav_fmu::limits::{MAX_CATEGORIES, MAX_STRING_BYTES, MAX_STRING_REFS, MAX_VALUE_REFS};
use std::ffi::{c_char, c_int};

impl Fuzzer<'_> {
    /// fmi3SetDebugLogging with no, known, unknown, over-long or too many categories.
    pub(super) fn debug_logging(&mut self, s: &Inst, sim: &mut Sim) -> Result<()> {
        let names: Vec<String> = match self.rng.random_range(0..7) {
            0 => vec![],
            1 => vec!["logAll".into()],
            2 => vec!["logEvents".into(), "logStatusError".into()],
            3 => vec!["logNothing".into()],
            4 => vec!["logAll".repeat(MAX_STRING_BYTES)],
            5 => vec!["logAll".into(); MAX_CATEGORIES + 1],
            _ => {
                // SAFETY: a null array with a non-zero count must be refused unread.
                let r = unsafe { (self.api.fmi3SetDebugLogging)(s.c, 1, 2, std::ptr::null()) };
                self.stats.null_arrays += 1;
                return self.expect(
                    s,
                    "fmi3SetDebugLogging(NULL categories)",
                    sim,
                    Expect::Refused,
                    r,
                );
            }
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
        let on = [0u8, 1, 1, 2][self.rng.random_range(0..4)];
        // SAFETY: our instance and `ptrs.len()` C strings.
        let r = unsafe { (self.api.fmi3SetDebugLogging)(s.c, on, ptrs.len(), ptrs.as_ptr()) };
        self.expect(s, "fmi3SetDebugLogging", sim, Expect::ok_if(valid), r)
    }

    /// A function of a capability this FMU does not have: fmi3Error in every state.
    pub(super) fn unsupported(&mut self, s: &Inst, sim: &mut Sim) -> Result<()> {
        let a = self.api;
        let c = s.c;
        let vr = [0u32, 1];
        let (mut x, mut n, mut b, mut q) = ([0.0f64; 4], [0usize; 4], [0u8; 6], [0 as c_int; 4]);
        let (mut k, mut u) = ([0u32; 4], [0u64; 4]);
        let which = self.rng.random_range(0..31);
        // SAFETY: our instance; every array has room for the counts passed.
        let r = unsafe {
            match which {
                0 => (a.fmi3EnterEventMode)(c),
                1 => (a.fmi3EnterStepMode)(c),
                2 => (a.fmi3EnterConfigurationMode)(c),
                3 => (a.fmi3ExitConfigurationMode)(c),
                4 => (a.fmi3GetClock)(c, vr.as_ptr(), 2, b.as_mut_ptr()),
                5 => (a.fmi3SetClock)(c, vr.as_ptr(), 2, b.as_ptr()),
                6 => (a.fmi3GetDirectionalDerivative)(
                    c,
                    vr.as_ptr(),
                    1,
                    vr.as_ptr(),
                    1,
                    x.as_ptr(),
                    1,
                    x.as_mut_ptr(),
                    1,
                ),
                7 => (a.fmi3GetAdjointDerivative)(
                    c,
                    vr.as_ptr(),
                    1,
                    vr.as_ptr(),
                    1,
                    x.as_ptr(),
                    1,
                    x.as_mut_ptr(),
                    1,
                ),
                8 => (a.fmi3GetOutputDerivatives)(
                    c,
                    vr.as_ptr(),
                    1,
                    [1i32].as_ptr(),
                    x.as_mut_ptr(),
                    1,
                ),
                9 => (a.fmi3GetNumberOfVariableDependencies)(c, 0, n.as_mut_ptr()),
                10 => (a.fmi3GetVariableDependencies)(
                    c,
                    0,
                    n.as_mut_ptr(),
                    k.as_mut_ptr(),
                    n.as_mut_ptr(),
                    q.as_mut_ptr(),
                    1,
                ),
                11 => (a.fmi3GetIntervalDecimal)(c, vr.as_ptr(), 1, x.as_mut_ptr(), q.as_mut_ptr()),
                12 => (a.fmi3GetIntervalFraction)(
                    c,
                    vr.as_ptr(),
                    1,
                    u.as_mut_ptr(),
                    u.as_mut_ptr(),
                    q.as_mut_ptr(),
                ),
                13 => (a.fmi3GetShiftDecimal)(c, vr.as_ptr(), 1, x.as_mut_ptr()),
                14 => (a.fmi3GetShiftFraction)(c, vr.as_ptr(), 1, u.as_mut_ptr(), u.as_mut_ptr()),
                15 => (a.fmi3SetIntervalDecimal)(c, vr.as_ptr(), 1, x.as_ptr()),
                16 => (a.fmi3SetIntervalFraction)(c, vr.as_ptr(), 1, u.as_ptr(), u.as_ptr()),
                17 => (a.fmi3SetShiftDecimal)(c, vr.as_ptr(), 1, x.as_ptr()),
                18 => (a.fmi3SetShiftFraction)(c, vr.as_ptr(), 1, u.as_ptr(), u.as_ptr()),
                19 => (a.fmi3EvaluateDiscreteStates)(c),
                20 => {
                    let [b0, b1, b2, b3, b4, _] = &mut b;
                    (a.fmi3UpdateDiscreteStates)(c, b0, b1, b2, b3, b4, x.as_mut_ptr())
                }
                21 => (a.fmi3EnterContinuousTimeMode)(c),
                22 => {
                    let [b0, b1, ..] = &mut b;
                    (a.fmi3CompletedIntegratorStep)(c, 1, b0, b1)
                }
                23 => (a.fmi3SetTime)(c, 1.0),
                24 => (a.fmi3SetContinuousStates)(c, x.as_ptr(), 4),
                25 => (a.fmi3GetContinuousStateDerivatives)(c, x.as_mut_ptr(), 4),
                26 => (a.fmi3GetEventIndicators)(c, x.as_mut_ptr(), 4),
                27 => (a.fmi3GetContinuousStates)(c, x.as_mut_ptr(), 4),
                28 => (a.fmi3GetNominalsOfContinuousStates)(c, x.as_mut_ptr(), 4),
                29 => (a.fmi3GetNumberOfContinuousStates)(c, n.as_mut_ptr()),
                _ => (a.fmi3ActivateModelPartition)(c, 0, 0.0),
            }
        };
        self.stats.unsupported += 1;
        self.expect(
            s,
            &format!("unsupported fmi3 function #{which}"),
            sim,
            Expect::Refused,
            r,
        )?;
        ensure!(
            n == [0; 4] && k == [0; 4] && u == [0; 4] && b == [0; 6] && x == [0.0; 4],
            "unsupported fmi3 function #{which} wrote an output"
        );
        Ok(())
    }

    /// The getters and setters of types without variables (Float32, Int8 … UInt32, Binary):
    /// allowed where their kind is, a no-op for no references, fmi3Error for any reference.
    pub(super) fn no_variables(&mut self, s: &Inst, sim: &mut Sim) -> Result<()> {
        let a = self.api;
        let c = s.c;
        let nvr = [0usize, 1, 2][self.rng.random_range(0..3)];
        let vr = [0u32, 1];
        let which = self.rng.random_range(0..14);
        let get = which % 2 == 0;
        let (mut f, mut i8s, mut u8s, mut i16s) = ([0f32; 2], [0i8; 2], [0u8; 2], [0i16; 2]);
        let (mut u16s, mut u32s, mut sizes) = ([0u16; 2], [0u32; 2], [0usize; 2]);
        let mut bins = [std::ptr::null::<u8>(); 2];
        // SAFETY: our instance; arrays of two elements for at most two references.
        let r = unsafe {
            match which {
                0 => (a.fmi3GetFloat32)(c, vr.as_ptr(), nvr, f.as_mut_ptr(), nvr),
                1 => (a.fmi3SetFloat32)(c, vr.as_ptr(), nvr, f.as_ptr(), nvr),
                2 => (a.fmi3GetInt8)(c, vr.as_ptr(), nvr, i8s.as_mut_ptr(), nvr),
                3 => (a.fmi3SetInt8)(c, vr.as_ptr(), nvr, i8s.as_ptr(), nvr),
                4 => (a.fmi3GetUInt8)(c, vr.as_ptr(), nvr, u8s.as_mut_ptr(), nvr),
                5 => (a.fmi3SetUInt8)(c, vr.as_ptr(), nvr, u8s.as_ptr(), nvr),
                6 => (a.fmi3GetInt16)(c, vr.as_ptr(), nvr, i16s.as_mut_ptr(), nvr),
                7 => (a.fmi3SetInt16)(c, vr.as_ptr(), nvr, i16s.as_ptr(), nvr),
                8 => (a.fmi3GetUInt16)(c, vr.as_ptr(), nvr, u16s.as_mut_ptr(), nvr),
                9 => (a.fmi3SetUInt16)(c, vr.as_ptr(), nvr, u16s.as_ptr(), nvr),
                10 => (a.fmi3GetUInt32)(c, vr.as_ptr(), nvr, u32s.as_mut_ptr(), nvr),
                11 => (a.fmi3SetUInt32)(c, vr.as_ptr(), nvr, u32s.as_ptr(), nvr),
                12 => (a.fmi3GetBinary)(
                    c,
                    vr.as_ptr(),
                    nvr,
                    sizes.as_mut_ptr(),
                    bins.as_mut_ptr(),
                    nvr,
                ),
                _ => (a.fmi3SetBinary)(c, vr.as_ptr(), nvr, sizes.as_ptr(), bins.as_ptr(), nvr),
            }
        };
        let allowed = if get {
            sim.st.readable()
        } else {
            sim.st.writable()
        };
        if nvr > 0 {
            self.stats.bad_refs += 1;
        }
        self.expect(
            s,
            &format!("getter/setter #{which} of a type without variables, {nvr} references"),
            sim,
            Expect::ok_if(allowed && nvr == 0),
            r,
        )
    }

    /// Counts and sizes past their bounds (refused unread), and a read of exactly
    /// MAX_VALUE_REFS references (accepted where reads are).
    pub(super) fn over_bound(&mut self, s: &Inst, sim: &mut Sim) -> Result<()> {
        let a = self.api;
        let c = s.c;
        let n = MAX_VALUE_REFS + 1;
        let mut strings = vec![std::ptr::null::<c_char>(); MAX_STRING_REFS + 1];
        let which = self.rng.random_range(0..6);
        if which == 5 {
            // Exactly at the bound: MAX_VALUE_REFS copies of one Float64 input or parameter.
            let Some(v) = self
                .v3
                .iter()
                .find(|v| matches!(v.what, super::model::What::Scalar(i) if self.vars[i].causality != Causality::Output && v.ty == entrynav_fmu::instance::Type3::Float64))
                .copied()
            else {
                return Ok(());
            };
            let vrs = vec![v.vr; MAX_VALUE_REFS];
            // SAFETY: MAX_VALUE_REFS references and values.
            let r = unsafe {
                (a.fmi3GetFloat64)(
                    c,
                    vrs.as_ptr(),
                    vrs.len(),
                    self.big_out.as_mut_ptr(),
                    vrs.len(),
                )
            };
            return self.expect(
                s,
                "fmi3GetFloat64 of MAX_VALUE_REFS references",
                sim,
                Expect::ok_if(sim.st.readable()),
                r,
            );
        }
        self.stats.over_bound += 1;
        // SAFETY: buffers of MAX_VALUE_REFS + 1 (MAX_STRING_REFS + 1) elements; the counts over
        // the bound are refused unread.
        let r = unsafe {
            match which {
                0 => (a.fmi3GetFloat64)(c, self.big_vr.as_ptr(), n, self.big_out.as_mut_ptr(), n),
                1 => (a.fmi3SetFloat64)(c, self.big_vr.as_ptr(), n, self.big_out.as_ptr(), n),
                2 => (a.fmi3GetString)(
                    c,
                    self.big_vr.as_ptr(),
                    MAX_STRING_REFS + 1,
                    strings.as_mut_ptr(),
                    MAX_STRING_REFS + 1,
                ),
                3 => (a.fmi3SetString)(
                    c,
                    self.big_vr.as_ptr(),
                    MAX_STRING_REFS + 1,
                    strings.as_ptr(),
                    MAX_STRING_REFS + 1,
                ),
                _ => (a.fmi3GetFloat64)(
                    c,
                    self.big_vr.as_ptr(),
                    usize::MAX / 16,
                    self.big_out.as_mut_ptr(),
                    usize::MAX / 16,
                ),
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
}
