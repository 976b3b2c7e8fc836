//! `entrynav fmu fuzz`: random FMI call sequences through our host against a model of the
//! co-simulation state machine; every illegal call must be answered with fmi2Error, nothing may
//! crash.

#![allow(non_snake_case)]

use super::*;
use mars_entry_nav::host::*;

/// Our model of the FMI 2.0 co-simulation state machine (as the FMU implements it).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum St {
    Instantiated,
    Init,
    Step,
    Terminated,
    Error,
}

pub(super) fn fuzz(file: &Path, cases: usize, calls: usize, seed: u64) -> Result<()> {
    let u = unpack(file)?;
    let m = u.model;
    let vars = variables(m);
    let guid = guid_of(m);
    let uri = file_uri(&u.dir.join("resources"));
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut counts = [0usize; 6];
    let mut illegal = 0usize;
    let n_vars = vars.len() as u32;
    for case in 0..cases {
        let s = Slave::new(&u, &format!("fuzz{case}"), &guid, &uri)?;
        let mut st = St::Instantiated;
        let mut time = 0.0;
        let mut states: Vec<(*mut c_void, St, f64)> = Vec::new();
        for _ in 0..calls {
            let op = rng.random_range(0..22u32);
            // Values: mostly valid, sometimes an unknown reference, NaN, or a wrong type.
            let vr = if rng.random_bool(0.1) {
                n_vars + rng.random_range(0..5u32)
            } else {
                rng.random_range(0..n_vars)
            };
            let var = vars.get(vr as usize);
            // SAFETY: our instance, valid buffers; the FMU must answer every call without crashing.
            let (status, legal): (c_int, Option<bool>) = unsafe {
                match op {
                    0 => {
                        let ok = (u.api.fmi2SetupExperiment)(
                            s.c,
                            0,
                            0.0,
                            0.0,
                            rng.random_bool(0.5) as c_int,
                            1e6,
                        );
                        (ok, Some(st == St::Instantiated))
                    }
                    1 => {
                        let r = (u.api.fmi2EnterInitializationMode)(s.c);
                        let legal = st == St::Instantiated;
                        if r == 0 {
                            st = St::Init;
                        }
                        (r, Some(legal))
                    }
                    2 => {
                        let r = (u.api.fmi2ExitInitializationMode)(s.c);
                        let legal = st == St::Init;
                        if r == 0 {
                            st = St::Step;
                        }
                        (r, if legal { None } else { Some(false) })
                    }
                    3..=5 => {
                        let h = [1.0, 0.1, 0.0, -1.0, f64::NAN][rng.random_range(0..5)];
                        let t = if rng.random_bool(0.85) {
                            time
                        } else {
                            time + 0.5
                        };
                        let r = (u.api.fmi2DoStep)(s.c, t, h, 0);
                        let legal = st == St::Step && h > 0.0 && t == time;
                        if r <= 1 {
                            time += h;
                        } else if r == 3 && legal {
                            st = St::Error;
                        }
                        (r, if legal { None } else { Some(false) })
                    }
                    6 => {
                        let r = (u.api.fmi2Terminate)(s.c);
                        let legal = st == St::Step;
                        if r == 0 {
                            st = St::Terminated;
                        }
                        (r, Some(legal))
                    }
                    7 => {
                        let r = (u.api.fmi2Reset)(s.c);
                        if r == 0 {
                            st = St::Instantiated;
                            time = 0.0;
                        }
                        (r, Some(true))
                    }
                    8 | 9 => {
                        let mut out = [0.0f64; 1];
                        let r = (u.api.fmi2GetReal)(s.c, &vr, 1, out.as_mut_ptr());
                        let legal =
                            st != St::Instantiated && var.is_some_and(|v| v.ty == Type::Real);
                        (r, if legal { None } else { Some(false) })
                    }
                    10 => {
                        let mut out = [0 as c_int; 1];
                        let r = (u.api.fmi2GetBoolean)(s.c, &vr, 1, out.as_mut_ptr());
                        let legal =
                            st != St::Instantiated && var.is_some_and(|v| v.ty == Type::Boolean);
                        (r, if legal { None } else { Some(false) })
                    }
                    11 | 12 => {
                        let x = [0.1, -0.4, f64::NAN, f64::INFINITY, 3.0][rng.random_range(0..5)];
                        let r = (u.api.fmi2SetReal)(s.c, &vr, 1, &x);
                        let legal = matches!(st, St::Instantiated | St::Init | St::Step)
                            && x.is_finite()
                            && var.is_some_and(|v| {
                                v.ty == Type::Real && v.causality == Causality::Input
                            });
                        (r, Some(legal))
                    }
                    13 => {
                        let b: c_int = rng.random_range(0..2);
                        let r = (u.api.fmi2SetBoolean)(s.c, &vr, 1, &b);
                        let legal = var.is_some_and(|v| {
                            v.ty == Type::Boolean
                                && match v.causality {
                                    Causality::Input => {
                                        matches!(st, St::Instantiated | St::Init | St::Step)
                                    }
                                    Causality::Parameter => {
                                        matches!(st, St::Instantiated | St::Init)
                                    }
                                    Causality::Output => false,
                                }
                        });
                        (r, Some(legal))
                    }
                    14 => {
                        let mut p: *mut c_void = std::ptr::null_mut();
                        let r = (u.api.fmi2GetFMUstate)(s.c, &mut p);
                        if r == 0 {
                            states.push((p, st, time));
                        }
                        (r, Some(true))
                    }
                    15 => match states.last().copied() {
                        Some((p, saved, saved_t)) => {
                            let r = (u.api.fmi2SetFMUstate)(s.c, p);
                            if r == 0 {
                                st = saved;
                                time = saved_t;
                            }
                            (r, Some(true))
                        }
                        None => (
                            (u.api.fmi2SetFMUstate)(s.c, std::ptr::null_mut()),
                            Some(false),
                        ),
                    },
                    16 => match states.pop() {
                        Some((mut p, saved, saved_t)) => {
                            let mut size = 0usize;
                            let r1 = (u.api.fmi2SerializedFMUstateSize)(s.c, p, &mut size);
                            let mut buf = vec![0u8; size];
                            let r2 = (u.api.fmi2SerializeFMUstate)(s.c, p, buf.as_mut_ptr(), size);
                            if !buf.is_empty() && rng.random_bool(0.3) {
                                let i = rng.random_range(0..buf.len());
                                buf[i] ^= 0x5a;
                            }
                            let mut q: *mut c_void = std::ptr::null_mut();
                            let r3 = (u.api.fmi2DeSerializeFMUstate)(
                                s.c,
                                buf.as_ptr(),
                                buf.len(),
                                &mut q,
                            );
                            let r4 = (u.api.fmi2FreeFMUstate)(s.c, &mut p);
                            if r3 == 0 {
                                states.push((q, saved, saved_t));
                            }
                            // Freeing twice: the second free sees NULL and is a no-op.
                            let r5 = (u.api.fmi2FreeFMUstate)(s.c, &mut p);
                            ensure!(
                                r1 == 0 && r2 == 0 && r4 == 0 && r5 == 0,
                                "state functions failed: {r1} {r2} {r4} {r5}"
                            );
                            (r3, None)
                        }
                        None => {
                            let garbage = [1u8, 2, 3];
                            let mut q: *mut c_void = std::ptr::null_mut();
                            (
                                (u.api.fmi2DeSerializeFMUstate)(s.c, garbage.as_ptr(), 3, &mut q),
                                Some(false),
                            )
                        }
                    },
                    17 => ((u.api.fmi2CancelStep)(s.c), Some(false)),
                    18 => {
                        let mut x = 0.0;
                        let d = 1.0;
                        (
                            (u.api.fmi2GetDirectionalDerivative)(s.c, &vr, 1, &vr, 1, &d, &mut x),
                            Some(false),
                        )
                    }
                    19 => {
                        let mut x = 0.0;
                        let r = (u.api.fmi2GetRealStatus)(s.c, 2, &mut x);
                        (r, Some(matches!(st, St::Step | St::Terminated)))
                    }
                    20 => {
                        // Null pointers where arrays are required.
                        let r = (u.api.fmi2GetReal)(s.c, std::ptr::null(), 3, std::ptr::null_mut());
                        (r, Some(false))
                    }
                    _ => {
                        let cat = c"logAll";
                        let p = cat.as_ptr();
                        let r = (u.api.fmi2SetDebugLogging)(s.c, 1, 1, &p);
                        (r, Some(true))
                    }
                }
            };
            counts[(status.clamp(0, 5)) as usize] += 1;
            match legal {
                Some(false) => {
                    illegal += 1;
                    ensure!(
                        status == 3,
                        "case {case}: illegal call (op {op}, state {st:?}) answered {status}, not fmi2Error"
                    );
                }
                Some(true) => ensure!(
                    status == 0,
                    "case {case}: legal call (op {op}, state {st:?}) answered {status}: {:?}",
                    s.messages().last()
                ),
                None => {}
            }
        }
        for (mut p, _, _) in states {
            // SAFETY: our instance and a state it handed out.
            unsafe { (u.api.fmi2FreeFMUstate)(s.c, &mut p) };
        }
        ensure!(
            s.messages().iter().all(|(_, m)| !m.is_empty()),
            "an empty log message"
        );
    }
    // Null and freed instances.
    // SAFETY: null is allowed everywhere.
    unsafe {
        (u.api.fmi2FreeInstance)(std::ptr::null_mut());
        ensure!((u.api.fmi2DoStep)(std::ptr::null_mut(), 0.0, 1.0, 0) == 3);
        ensure!((u.api.fmi2Terminate)(std::ptr::null_mut()) == 3);
    }
    println!(
        "fuzz {}: {cases} sequences x {calls} calls, no crash; statuses OK {} / Warning {} / Discard {} / Error {}; {illegal} illegal calls, every one answered fmi2Error",
        m.identifier(),
        counts[0],
        counts[1],
        counts[2],
        counts[3]
    );
    let _ = xml::LOG_CATEGORIES;
    Ok(())
}
