//! The FMI 3.0 functions this FMU does not support (fmi3Error in every state, no output
//! written), and the getters and setters of the types it has no variables of (Float32, Int8 …
//! UInt32, Binary: a no-op for no references, fmi3Error for any).

use super::super::fuzzer::Fuzzer;
use super::super::model::{Expect, Sim};
use super::Fmi3;
use anyhow::{Result, ensure};
use entrynav_fmi_host::{Api3, Inst3, Slave3};
use rand::RngExt;
use std::ffi::c_int;

impl Fuzzer<Fmi3> {
    /// A function of a capability this FMU does not have: fmi3Error in every state.
    pub(super) fn unsupported(&mut self, s: &Slave3, sim: &mut Sim) -> Result<()> {
        let which = self.rng.random_range(0..31);
        let mut o = Outputs::default();
        let r = call_unsupported(&s.api, s.c, which, &mut o);
        self.stats.unsupported += 1;
        self.expect(
            s,
            &format!("unsupported fmi3 function #{which}"),
            sim,
            Expect::Refused,
            r,
        )?;
        ensure!(
            o == Outputs::default(),
            "unsupported fmi3 function #{which} wrote an output"
        );
        Ok(())
    }

    /// The getters and setters of types without variables (Float32, Int8 … UInt32, Binary):
    /// allowed where their kind is, a no-op for no references, fmi3Error for any reference.
    pub(super) fn no_variables(&mut self, s: &Slave3, sim: &mut Sim) -> Result<()> {
        let a = std::sync::Arc::clone(&s.api);
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
}

/// The output arrays an unsupported function is given (it must write none of them).
#[derive(Debug, Default, PartialEq)]
struct Outputs {
    x: [f64; 4],
    n: [usize; 4],
    b: [u8; 6],
    q: [c_int; 4],
    k: [u32; 4],
    u: [u64; 4],
}

/// Unsupported function `which` (0 to 30) on the instance `c`, with the arrays of `o`.
fn call_unsupported(a: &Api3, c: Inst3, which: u32, o: &mut Outputs) -> i32 {
    let vr = [0u32, 1];
    let Outputs { x, n, b, q, k, u } = o;
    // SAFETY: the instance token (any value is refused or used); every array has room for the
    // counts passed.
    unsafe {
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
            8 => {
                (a.fmi3GetOutputDerivatives)(c, vr.as_ptr(), 1, [1i32].as_ptr(), x.as_mut_ptr(), 1)
            }
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
                let [b0, b1, b2, b3, b4, _] = b;
                (a.fmi3UpdateDiscreteStates)(c, b0, b1, b2, b3, b4, x.as_mut_ptr())
            }
            21 => (a.fmi3EnterContinuousTimeMode)(c),
            22 => {
                let [b0, b1, ..] = b;
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
    }
}
