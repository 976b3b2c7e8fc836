//! The FMI 3.0 interface through its exported functions, in process: the same run as through
//! FMI 2.0 bit for bit, the arrays and the structural parameter, the FMI 3.0 type rules
//! (Enumerations through Int64, nValues), the state machine and its messages in FMI 3.0 terms,
//! the refused capabilities, and FMU states.

use entrynav_fmu::ffi::*;
use entrynav_fmu::guid_of;
use entrynav_fmu::vars::fmi3::extras;
use entrynav_fmu::vars::{Key, Model, ModelSpec, variables};
use std::ffi::{CStr, CString, c_char, c_int, c_void};
use std::sync::Mutex;

mod common;

type Log = Mutex<Vec<(i32, String)>>;

extern "C" fn logger3(env: *mut c_void, status: c_int, _cat: *const c_char, msg: *const c_char) {
    // SAFETY: env is the test's `Log`; msg is a C string from the FMU.
    let (log, text) = unsafe { (&*(env as *const Log), CStr::from_ptr(msg).to_string_lossy()) };
    log.lock().unwrap().push((status, text.into_owned()));
}

struct Inst3 {
    c: *mut c_void,
    log: Box<Log>,
}

const OK: c_int = 0;
const ERROR: c_int = 3;

impl Inst3 {
    fn new(model: Model) -> Inst3 {
        Inst3::with_token(&guid_of(model), false).expect("instantiated")
    }

    fn with_token(token: &str, event_mode: bool) -> Result<Inst3, Vec<String>> {
        let log: Box<Log> = Box::new(Mutex::new(Vec::new()));
        let name = CString::new("fmi3 test").unwrap();
        let token = CString::new(token).unwrap();
        // SAFETY: valid arguments; the log outlives the instance.
        let c = unsafe {
            fmi3InstantiateCoSimulation(
                name.as_ptr(),
                token.as_ptr(),
                std::ptr::null(),
                0,
                0,
                event_mode as u8,
                0,
                std::ptr::null(),
                0,
                &*log as *const Log as *mut c_void,
                Some(logger3),
                std::ptr::null(),
            )
        };
        if c.is_null() {
            return Err(log.lock().unwrap().iter().map(|m| m.1.clone()).collect());
        }
        Ok(Inst3 { c, log })
    }

    fn messages(&self) -> Vec<String> {
        self.log
            .lock()
            .unwrap()
            .iter()
            .map(|m| m.1.clone())
            .collect()
    }

    fn last(&self) -> String {
        self.messages().last().cloned().unwrap_or_default()
    }

    fn init(&self) {
        // SAFETY: a live instance.
        unsafe {
            assert_eq!(fmi3EnterInitializationMode(self.c, 0, 0.0, 0.0, 0, 0.0), OK);
            assert_eq!(fmi3ExitInitializationMode(self.c), OK);
        }
    }

    fn step(&self, t: f64) -> f64 {
        let (mut ev, mut term, mut early, mut last) = (7u8, 7u8, 7u8, -1.0);
        // SAFETY: a live instance, pointers to locals.
        let s = unsafe { fmi3DoStep(self.c, t, 1.0, 0, &mut ev, &mut term, &mut early, &mut last) };
        assert_eq!(s, OK, "{:?}", self.messages());
        assert_eq!((ev, term, early), (0, 0, 0));
        last
    }

    fn float64(&self, vrs: &[u32], n: usize) -> (c_int, Vec<f64>) {
        let mut out = vec![f64::NAN; n];
        // SAFETY: `n` writable values.
        let s = unsafe { fmi3GetFloat64(self.c, vrs.as_ptr(), vrs.len(), out.as_mut_ptr(), n) };
        (s, out)
    }
}

impl Drop for Inst3 {
    fn drop(&mut self) {
        // SAFETY: a live instance.
        unsafe { fmi3FreeInstance(self.c) };
    }
}

fn vr(model: Model, key: Key) -> u32 {
    variables(model).iter().find(|v| v.key == key).unwrap().vr
}

#[test]
fn an_fmi3_run_equals_the_fmi2_run_bit_for_bit_and_the_arrays_hold_the_scalars() {
    let model = Model::Combined;
    let vars = variables(model);
    let reals: Vec<u32> = vars
        .iter()
        .filter(|v| v.ty == entrynav_fmu::vars::Type::Real)
        .map(|v| v.vr)
        .collect();
    let v2 = common::Inst::new(model);
    v2.init();
    let v3 = Inst3::new(model);
    v3.init();
    let x = extras(&ModelSpec::generic(model));
    let arrays: Vec<u32> = x.iter().filter(|v| v.is_array()).map(|v| v.vr).collect();
    let est: Vec<u32> = (0..12).map(|i| vr(model, Key::EstX(i))).collect();
    let sig: Vec<u32> = (0..12).map(|i| vr(model, Key::EstSigma(i))).collect();
    for k in 0..120 {
        let t = k as f64;
        v2.step(t, 1.0);
        assert_eq!(v3.step(t), t + 1.0);
        let mut a = vec![f64::NAN; reals.len()];
        // SAFETY: a live instance; `reals.len()` values.
        let s2 = unsafe { fmi2GetReal(v2.c, reals.as_ptr(), reals.len(), a.as_mut_ptr()) };
        assert_eq!(s2, OK);
        let (s, b) = v3.float64(&reals, reals.len());
        assert_eq!(s, OK);
        assert_eq!(
            a.iter().map(|x| x.to_bits()).collect::<Vec<_>>(),
            b.iter().map(|x| x.to_bits()).collect::<Vec<_>>()
        );
        let (s, arr) = v3.float64(&arrays, 12 + 12 + 144);
        assert_eq!(s, OK);
        let (_, e) = v3.float64(&est, 12);
        let (_, g) = v3.float64(&sig, 12);
        assert_eq!(arr[..12], e[..]);
        assert_eq!(arr[12..24], g[..]);
        for i in 0..12 {
            let p = arr[24 + i * 12 + i];
            assert!((p.sqrt() - g[i]).abs() <= 1e-12 * g[i], "slot {i}");
        }
        let (_, time) = v3.float64(&[x[0].vr], 1);
        assert_eq!(time[0], t + 1.0);
    }
}

#[test]
fn fmi3_type_rules_nvalues_and_the_structural_parameter() {
    let model = Model::Combined;
    let spec = ModelSpec::generic(model);
    let x = extras(&spec);
    let slots = x.iter().find(|v| v.name == "n_state_slots").unwrap().vr;
    let est = x.iter().find(|v| v.name == "est_x").unwrap().vr;
    let status = vr(model, Key::NavStatus);
    let n_states = vr(model, Key::NStates);
    let i = Inst3::new(model);
    i.init();
    i.step(0.0);
    // SAFETY: live instance and local buffers of the sizes passed.
    unsafe {
        let mut n = 0u64;
        assert_eq!(fmi3GetUInt64(i.c, &slots, 1, &mut n, 1), OK);
        assert_eq!(n, 12);
        // The Enumeration reads through Int64, not Int32; the plain Integer through Int32.
        let mut e = -1i64;
        assert_eq!(fmi3GetInt64(i.c, &status, 1, &mut e, 1), OK);
        assert_eq!(e, 1, "running");
        let mut e32 = -1i32;
        assert_eq!(fmi3GetInt32(i.c, &status, 1, &mut e32, 1), ERROR);
        assert!(
            i.last().contains("is a Int64 variable, not Int32"),
            "{}",
            i.last()
        );
        assert_eq!(fmi3GetInt32(i.c, &n_states, 1, &mut e32, 1), OK);
        assert!(e32 > 0);
        // nValues must be what the references hold.
        let mut buf = [0.0f64; 12];
        assert_eq!(fmi3GetFloat64(i.c, &est, 1, buf.as_mut_ptr(), 11), ERROR);
        assert!(
            i.last()
                .contains("nValues = 11, but the 1 variables hold 12 values")
        );
        // The structural parameter accepts only its own value, and only until initialisation
        // ends (fixed variability); outputs cannot be set.
        let twelve = 12u64;
        let thirteen = 13u64;
        assert_eq!(fmi3SetUInt64(i.c, &slots, 1, &twelve, 1), ERROR);
        assert!(
            i.last().contains("cannot be set after initialisation"),
            "{}",
            i.last()
        );
        let fresh = Inst3::new(model);
        assert_eq!(fmi3SetUInt64(fresh.c, &slots, 1, &twelve, 1), OK);
        assert_eq!(fmi3SetUInt64(fresh.c, &slots, 1, &thirteen, 1), ERROR);
        assert!(
            fresh.last().contains("'n_state_slots' is fixed at 12"),
            "{}",
            fresh.last()
        );
        assert_eq!(fmi3SetFloat64(i.c, &est, 1, buf.as_ptr(), 12), ERROR);
        // Types without variables: fine with no references, an error with one.
        let mut f = 0.0f32;
        assert_eq!(fmi3GetFloat32(i.c, std::ptr::null(), 0, &mut f, 0), OK);
        assert_eq!(fmi3GetFloat32(i.c, &est, 1, &mut f, 1), ERROR);
        assert!(i.last().contains("no Float32 variables"));
        // A null array with a count is refused, not read.
        assert_eq!(
            fmi3GetFloat64(i.c, std::ptr::null(), 3, buf.as_mut_ptr(), 3),
            ERROR
        );
    }
    assert!(
        i.messages().iter().all(|m| !m.contains("fmi2")),
        "{:?}",
        i.messages()
    );
}

#[test]
fn the_fmi3_state_machine_speaks_fmi3_and_refuses_what_this_fmu_lacks() {
    let i = Inst3::new(Model::Truth);
    let r = vr(Model::Truth, Key::TruthSph(0));
    let mut v = 0.0;
    // SAFETY: a live instance; locals.
    unsafe {
        assert_eq!(
            fmi3DoStep(
                i.c,
                0.0,
                1.0,
                0,
                std::ptr::null_mut(),
                std::ptr::null_mut(),
                std::ptr::null_mut(),
                std::ptr::null_mut()
            ),
            ERROR
        );
        assert!(
            i.last().starts_with("fmi3DoStep: Illegal call sequence"),
            "{}",
            i.last()
        );
        assert_eq!(fmi3GetFloat64(i.c, &r, 1, &mut v, 1), ERROR);
        assert!(
            i.last()
                .starts_with("fmi3GetFloat64: Illegal call sequence"),
            "{}",
            i.last()
        );
        assert_eq!(fmi3EnterInitializationMode(i.c, 0, 0.0, 5.0, 0, 0.0), ERROR);
        assert!(i.last().contains("startTime must be 0"), "{}", i.last());
        assert_eq!(fmi3EnterEventMode(i.c), ERROR);
        assert!(i.last().contains("hasEventMode = false"));
        assert_eq!(fmi3EnterConfigurationMode(i.c), ERROR);
        assert_eq!(fmi3SetTime(i.c, 1.0), ERROR);
        assert_eq!(fmi3EnterInitializationMode(i.c, 0, 0.0, 0.0, 1, 300.0), OK);
        assert_eq!(fmi3ExitInitializationMode(i.c), OK);
        assert_eq!(
            fmi3DoStep(
                i.c,
                3.0,
                1.0,
                0,
                std::ptr::null_mut(),
                std::ptr::null_mut(),
                std::ptr::null_mut(),
                std::ptr::null_mut()
            ),
            ERROR
        );
        assert!(i.last().contains("not the current time"), "{}", i.last());
        assert_eq!(fmi3Terminate(i.c), OK);
        assert_eq!(fmi3GetFloat64(i.c, &r, 1, &mut v, 1), OK);
        assert!(v > 3.3e6);
        assert_eq!(fmi3Reset(i.c), OK);
    }
    assert!(
        i.messages()
            .iter()
            .all(|m| !m.contains("fmi2") && !m.is_empty())
    );
    // Event mode and wrong tokens are refused at instantiation, in FMI 3.0 terms.
    let e = Inst3::with_token(&guid_of(Model::Truth), true)
        .err()
        .unwrap();
    assert!(e[0].contains("eventModeUsed"), "{e:?}");
    let e = Inst3::with_token("{nope}", false).err().unwrap();
    assert!(
        e[0].starts_with("fmi3InstantiateCoSimulation") && e[0].contains("instantiation token"),
        "{e:?}"
    );
}

#[test]
fn an_instance_answers_only_the_interface_that_created_it() {
    let i3 = Inst3::new(Model::Truth);
    let i2 = common::Inst::new(Model::Truth);
    let mut s: *mut c_void = std::ptr::null_mut();
    // SAFETY: live instances; locals.
    unsafe {
        assert_eq!(fmi2EnterInitializationMode(i3.c), ERROR);
        assert!(i3.last().starts_with("fmi2EnterInitializationMode: this instance was created by fmi3InstantiateCoSimulation"), "{}", i3.last());
        assert_eq!(
            fmi3EnterInitializationMode(i2.c, 0, 0.0, 0.0, 0, 0.0),
            ERROR
        );
        assert_eq!(fmi3Terminate(i2.c), ERROR);
        assert!(
            i2.last().contains("created by fmi2Instantiate"),
            "{}",
            i2.last()
        );
        // A foreign FMU state is named in FMI 3.0 spelling.
        assert_eq!(fmi3SetFMUState(i3.c, std::ptr::null_mut()), ERROR);
        assert!(
            i3.last().contains("FMUState") && !i3.last().contains("FMUstate"),
            "{}",
            i3.last()
        );
        assert_eq!(fmi3GetFMUState(i3.c, &mut s), OK);
        assert_eq!(fmi3FreeFMUState(i3.c, &mut s), OK);
    }
    // Both still work through their own interface.
    i2.init();
    i3.init();
}

#[test]
fn an_fmi3_fmu_state_serialized_and_restored_replays_the_run() {
    let model = Model::Combined;
    let watch = [
        vr(model, Key::EstX(0)),
        vr(model, Key::Nis),
        vr(model, Key::TruthSph(3)),
    ];
    let i = Inst3::new(model);
    i.init();
    for k in 0..40 {
        i.step(k as f64);
    }
    let mut s: *mut c_void = std::ptr::null_mut();
    let mut size = 0usize;
    // SAFETY: a live instance; locals and buffers of the sizes passed.
    let bytes = unsafe {
        assert_eq!(fmi3GetFMUState(i.c, &mut s), OK);
        assert_eq!(fmi3SerializedFMUStateSize(i.c, s, &mut size), OK);
        let mut b = vec![0u8; size];
        assert_eq!(fmi3SerializeFMUState(i.c, s, b.as_mut_ptr(), size), OK);
        b
    };
    let run = |from: usize| -> Vec<u64> {
        (from..from + 30)
            .flat_map(|k| {
                i.step(k as f64);
                i.float64(&watch, 3).1.into_iter().map(f64::to_bits)
            })
            .collect()
    };
    let first = run(40);
    let mut r: *mut c_void = std::ptr::null_mut();
    // SAFETY: as above.
    unsafe {
        assert_eq!(
            fmi3DeserializeFMUState(i.c, bytes.as_ptr(), bytes.len(), &mut r),
            OK
        );
        assert_eq!(fmi3SetFMUState(i.c, r), OK);
    }
    assert_eq!(run(40), first);
    // SAFETY: as above; a truncated state is refused.
    unsafe {
        let mut q: *mut c_void = std::ptr::null_mut();
        assert_eq!(
            fmi3DeserializeFMUState(i.c, bytes.as_ptr(), bytes.len() / 2, &mut q),
            ERROR
        );
        assert!(q.is_null());
        assert_eq!(fmi3FreeFMUState(i.c, &mut s), OK);
        assert_eq!(fmi3FreeFMUState(i.c, &mut r), OK);
        assert!(s.is_null() && r.is_null());
    }
}
