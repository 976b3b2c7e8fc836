//! The C API in process: lifecycle, state save/restore bit for bit, and random call sequences
//! (proptest) in which every illegal call must be answered with fmi2Error and nothing may panic
//! through the boundary.

use entrynav_fmu::ffi::*;
use entrynav_fmu::vars::{Causality, Key, Model, Type, variables};
use entrynav_fmu::{guid_of, model_description};
use proptest::prelude::*;
use std::ffi::{CStr, CString, c_char, c_int, c_void};
use std::sync::Mutex;

type Log = Mutex<Vec<(i32, String)>>;

extern "C" fn logger(
    env: *mut c_void,
    _name: *const c_char,
    status: c_int,
    _cat: *const c_char,
    msg: *const c_char,
) {
    // SAFETY: env is the test's `Log`; msg a C string from the FMU.
    let (log, text) = unsafe { (&*(env as *const Log), CStr::from_ptr(msg).to_string_lossy()) };
    log.lock().unwrap().push((status, text.into_owned()));
}

fn callbacks(log: &Log) -> CallbackFunctions {
    // SAFETY: x86-64 System V passes the five fixed arguments of a variadic call exactly as for
    // this non-variadic function, and the FMU passes no variadic arguments.
    let f: LoggerFn = unsafe {
        std::mem::transmute::<
            extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char),
            LoggerFn,
        >(logger)
    };
    CallbackFunctions {
        logger: Some(f),
        allocate_memory: None,
        free_memory: None,
        step_finished: None,
        component_environment: log as *const Log as *mut c_void,
    }
}

struct Inst {
    c: *mut c_void,
    _cb: Box<CallbackFunctions>,
    log: Box<Log>,
}

impl Inst {
    fn new(model: Model) -> Inst {
        let log: Box<Log> = Box::new(Mutex::new(Vec::new()));
        let cb = Box::new(callbacks(&log));
        let name = CString::new("test").unwrap();
        let guid = CString::new(guid_of(model)).unwrap();
        let res = CString::new("file:///nonexistent/resources").unwrap();
        // SAFETY: valid arguments.
        let c =
            unsafe { fmi2Instantiate(name.as_ptr(), 1, guid.as_ptr(), res.as_ptr(), &*cb, 0, 0) };
        assert!(!c.is_null());
        Inst { c, _cb: cb, log }
    }

    fn last(&self) -> String {
        self.log
            .lock()
            .unwrap()
            .last()
            .map(|m| m.1.clone())
            .unwrap_or_default()
    }

    fn init(&self) {
        // SAFETY: our instance.
        unsafe {
            assert_eq!(fmi2SetupExperiment(self.c, 0, 0.0, 0.0, 0, 0.0), 0);
            assert_eq!(fmi2EnterInitializationMode(self.c), 0);
            assert_eq!(fmi2ExitInitializationMode(self.c), 0, "{}", self.last());
        }
    }

    fn reals(&self, vrs: &[u32]) -> Vec<u64> {
        let mut v = vec![0.0; vrs.len()];
        // SAFETY: sized buffers.
        assert_eq!(
            unsafe { fmi2GetReal(self.c, vrs.as_ptr(), vrs.len(), v.as_mut_ptr()) },
            0
        );
        v.iter().map(|x| x.to_bits()).collect()
    }
}

impl Drop for Inst {
    fn drop(&mut self) {
        // SAFETY: our instance.
        unsafe { fmi2FreeInstance(self.c) };
    }
}

fn real_outputs(model: Model) -> Vec<u32> {
    variables(model)
        .into_iter()
        .filter(|v| v.causality == Causality::Output && v.ty == Type::Real)
        .map(|v| v.vr)
        .collect()
}

#[test]
fn xml_mentions_every_variable() {
    for m in Model::ALL {
        let xml = model_description(m);
        for v in variables(m) {
            assert!(xml.contains(&format!("name=\"{}\" valueReference=\"{}\"", v.name, v.vr)));
        }
    }
}

#[test]
fn state_restore_and_serialization_reproduce_the_run_bitwise() {
    let a = Inst::new(Model::Combined);
    a.init();
    let outs = real_outputs(Model::Combined);
    let bank = variables(Model::Combined)
        .iter()
        .find(|v| v.key == Key::Bank)
        .unwrap()
        .vr;
    let step = |i: &Inst, k: usize| {
        let b = if k > 50 { 0.2 } else { 0.0 };
        // SAFETY: our instance.
        unsafe {
            assert_eq!(fmi2SetReal(i.c, &bank, 1, &b), 0);
            assert!(fmi2DoStep(i.c, k as f64, 1.0, 0) <= 1, "{}", i.last());
        }
        i.reals(&outs)
    };
    for k in 0..40 {
        step(&a, k);
    }
    let mut st: *mut c_void = std::ptr::null_mut();
    let mut size = 0usize;
    // SAFETY: our instance and state.
    let bytes = unsafe {
        assert_eq!(fmi2GetFMUstate(a.c, &mut st), 0);
        assert_eq!(fmi2SerializedFMUstateSize(a.c, st, &mut size), 0);
        let mut buf = vec![0u8; size];
        assert_eq!(fmi2SerializeFMUstate(a.c, st, buf.as_mut_ptr(), size), 0);
        assert_eq!(
            fmi2SerializeFMUstate(a.c, st, buf.as_mut_ptr(), size - 1),
            3
        );
        buf
    };
    let first: Vec<_> = (40..120).map(|k| step(&a, k)).collect();
    // SAFETY: our instance and state.
    unsafe { assert_eq!(fmi2SetFMUstate(a.c, st), 0) };
    let again: Vec<_> = (40..120).map(|k| step(&a, k)).collect();
    assert_eq!(first, again);
    let b = Inst::new(Model::Combined);
    let mut st2: *mut c_void = std::ptr::null_mut();
    // SAFETY: our instance; bytes from the serializer.
    unsafe {
        assert_eq!(
            fmi2DeSerializeFMUstate(b.c, bytes.as_ptr(), bytes.len(), &mut st2),
            0
        );
        assert_eq!(fmi2SetFMUstate(b.c, st2), 0);
        // A state belongs to the instance that made it.
        assert_eq!(fmi2SetFMUstate(b.c, st), 3);
        assert!(b.last().contains("not a state of this instance"));
    }
    let restored: Vec<_> = (40..120).map(|k| step(&b, k)).collect();
    assert_eq!(first, restored);
    // SAFETY: our instances and states; a freed state is NULL afterwards, freeing NULL is a no-op.
    unsafe {
        assert_eq!(fmi2FreeFMUstate(a.c, &mut st), 0);
        assert!(st.is_null());
        assert_eq!(fmi2FreeFMUstate(a.c, &mut st), 0);
        assert_eq!(fmi2FreeFMUstate(b.c, &mut st2), 0);
    }
}

#[test]
fn instances_are_send_and_independent_across_threads() {
    let outs = real_outputs(Model::Combined);
    let run = |seed: i32| {
        let i = Inst::new(Model::Combined);
        let seed_vr = variables(Model::Combined)
            .iter()
            .find(|v| v.key == Key::Seed)
            .unwrap()
            .vr;
        // SAFETY: our instance.
        unsafe { assert_eq!(fmi2SetInteger(i.c, &seed_vr, 1, &seed), 0) };
        i.init();
        (0..60)
            .map(|k| {
                // SAFETY: our instance.
                unsafe { assert_eq!(fmi2DoStep(i.c, k as f64, 1.0, 0), 0) };
                i.reals(&outs)
            })
            .collect::<Vec<_>>()
    };
    let solo: Vec<_> = (1..=4).map(run).collect();
    let threaded: Vec<_> = std::thread::scope(|s| {
        let hs: Vec<_> = (1..=4).map(|seed| s.spawn(move || run(seed))).collect();
        hs.into_iter().map(|h| h.join().unwrap()).collect()
    });
    assert_eq!(solo, threaded);
}

#[derive(Debug, Clone, Copy, PartialEq)]
enum Ph {
    Inst,
    Init,
    Step,
    Term,
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, .. ProptestConfig::default() })]

    /// Random call sequences: illegal calls get fmi2Error, legal ones succeed, nothing panics.
    #[test]
    fn random_call_sequences(ops in prop::collection::vec((0u8..14, 0u32..200, -2.0f64..2.0), 1..40), model in 0usize..3) {
        let model = Model::ALL[model];
        let vars = variables(model);
        let i = Inst::new(model);
        let mut ph = Ph::Inst;
        let mut t = 0.0;
        for (op, vr, x) in ops {
            let var = vars.get(vr as usize);
            // SAFETY: our instance; valid buffers.
            let (st, legal) = unsafe {
                match op {
                    0 => (fmi2SetupExperiment(i.c, 0, 0.0, 0.0, 0, 0.0), Some(ph == Ph::Inst)),
                    1 => {
                        let r = fmi2EnterInitializationMode(i.c);
                        let l = ph == Ph::Inst;
                        if r == 0 { ph = Ph::Init; }
                        (r, Some(l))
                    }
                    2 => {
                        let r = fmi2ExitInitializationMode(i.c);
                        let l = ph == Ph::Init;
                        if r == 0 { ph = Ph::Step; }
                        (r, Some(l))
                    }
                    3 | 4 => {
                        let h = if x > -1.5 { 1.0 } else { x };
                        let r = fmi2DoStep(i.c, t, h, 0);
                        let l = ph == Ph::Step && h > 0.0;
                        if r <= 1 { t += h; }
                        (r, if l { None } else { Some(false) })
                    }
                    5 => {
                        let r = fmi2Terminate(i.c);
                        let l = ph == Ph::Step;
                        if r == 0 { ph = Ph::Term; }
                        (r, Some(l))
                    }
                    6 => {
                        let r = fmi2Reset(i.c);
                        if r == 0 { ph = Ph::Inst; t = 0.0; }
                        (r, Some(true))
                    }
                    7 => {
                        let mut out = 0.0;
                        let r = fmi2GetReal(i.c, &vr, 1, &mut out);
                        let l = ph != Ph::Inst && var.is_some_and(|v| v.ty == Type::Real);
                        (r, if l { None } else { Some(false) })
                    }
                    8 => {
                        let v = if x > 1.9 { f64::NAN } else { x };
                        let r = fmi2SetReal(i.c, &vr, 1, &v);
                        let l = ph != Ph::Term && v.is_finite()
                            && var.is_some_and(|d| d.ty == Type::Real && d.causality == Causality::Input);
                        (r, Some(l))
                    }
                    9 => {
                        let b = (x > 0.0) as c_int;
                        let r = fmi2SetBoolean(i.c, &vr, 1, &b);
                        let l = var.is_some_and(|d| d.ty == Type::Boolean && match d.causality {
                            Causality::Input => ph != Ph::Term,
                            Causality::Parameter => matches!(ph, Ph::Inst | Ph::Init),
                            Causality::Output => false,
                        });
                        (r, Some(l))
                    }
                    10 => (fmi2CancelStep(i.c), Some(false)),
                    11 => {
                        let mut v = 0;
                        let r = fmi2GetBooleanStatus(i.c, 3, &mut v);
                        (r, Some(matches!(ph, Ph::Step | Ph::Term)))
                    }
                    12 => (fmi2GetReal(i.c, std::ptr::null(), 2, std::ptr::null_mut()), Some(false)),
                    _ => {
                        let mut s: *mut c_void = std::ptr::null_mut();
                        let r1 = fmi2GetFMUstate(i.c, &mut s);
                        let r2 = fmi2SetFMUstate(i.c, s);
                        let r3 = fmi2FreeFMUstate(i.c, &mut s);
                        prop_assert_eq!((r1, r2, r3), (0, 0, 0), "{}", i.last());
                        (0, Some(true))
                    }
                }
            };
            match legal {
                Some(false) => {
                    prop_assert_eq!(st, 3, "illegal op {} in {:?} answered {}", op, ph, st);
                    prop_assert!(!i.last().is_empty());
                }
                Some(true) => prop_assert_eq!(st, 0, "legal op {} in {:?} answered {}: {}", op, ph, st, i.last()),
                None => prop_assert!(st <= 3),
            }
        }
    }
}

#[test]
fn null_and_bad_instantiation() {
    let log: Log = Mutex::new(Vec::new());
    let cb = callbacks(&log);
    let name = CString::new("x").unwrap();
    let guid = CString::new(guid_of(Model::Filter)).unwrap();
    let bad = CString::new("{bad}").unwrap();
    // SAFETY: exercising null and wrong arguments, all of which the FMU must reject.
    unsafe {
        assert!(
            fmi2Instantiate(name.as_ptr(), 1, bad.as_ptr(), std::ptr::null(), &cb, 0, 0).is_null()
        );
        assert!(
            fmi2Instantiate(name.as_ptr(), 0, guid.as_ptr(), std::ptr::null(), &cb, 0, 0).is_null()
        );
        assert!(
            fmi2Instantiate(
                std::ptr::null(),
                1,
                guid.as_ptr(),
                std::ptr::null(),
                &cb,
                0,
                0
            )
            .is_null()
        );
        assert!(
            fmi2Instantiate(
                name.as_ptr(),
                1,
                guid.as_ptr(),
                std::ptr::null(),
                std::ptr::null(),
                0,
                0
            )
            .is_null()
        );
        fmi2FreeInstance(std::ptr::null_mut());
        assert_eq!(fmi2DoStep(std::ptr::null_mut(), 0.0, 1.0, 0), 3);
        // Without a resource location a built-in scenario still works.
        let c = fmi2Instantiate(name.as_ptr(), 1, guid.as_ptr(), std::ptr::null(), &cb, 0, 1);
        assert!(!c.is_null());
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 1, 5.0), 0);
        assert_eq!(fmi2EnterInitializationMode(c), 0);
        assert_eq!(fmi2ExitInitializationMode(c), 0);
        assert_eq!(fmi2DoStep(c, 0.0, 6.0, 0), 3);
        fmi2FreeInstance(c);
    }
    let msgs = log.lock().unwrap();
    assert!(msgs.iter().any(|m| m.1.contains("does not match")));
    assert!(msgs.iter().any(|m| m.1.contains("model exchange")));
    assert!(msgs.iter().any(|m| m.1.contains("after stopTime")));
}

/// The filter FMU's `bank_angle` input reaches the filter: fed the measurements of a truth that
/// flies a bank profile, with that profile as its input, it equals the in-process filter told
/// the same bank, differs from one left at bank 0, and a saved state (the replay log records the
/// bank with the other inputs) reproduces the rest of the run bit for bit.
#[test]
fn filter_fmu_bank_input_reaches_the_filter_and_is_restored() {
    use entrynav::estimation::nav::FilterKind;
    use entrynav::scenario::{Scenario, ScenarioConfig};
    use entrynav::sensors::MeasurementEpoch;
    use entrynav::sim::engine::{Navigator, TruthSensors};
    use entrynav_fmu::vars::Slot;
    use std::sync::Arc;

    let (name, filter, seed) = ("msl-pressure", "ekf", 3u64);
    let sc = Arc::new(
        Scenario::build(
            ScenarioConfig::builtin(name).unwrap(),
            &entrynav::files::no_files,
        )
        .unwrap(),
    );
    let bank_of = |k: usize| if k < 40 { 0.0 } else { 0.7 };
    // The truth's epochs: the filter gets those of step k at step k + 1 (split pair).
    let mut truth = TruthSensors::new(Arc::clone(&sc), seed, false);
    let mut epochs: Vec<Option<MeasurementEpoch>> = vec![None];
    for k in 0..150 {
        truth.do_step(k as f64, 1.0, bank_of(k), &[]).unwrap();
        epochs.push(truth.last_epoch().cloned());
    }
    let vars = variables(Model::Filter);
    let vr = |key: Key| vars.iter().find(|v| v.key == key).unwrap().vr;
    let est: Vec<u32> = (0..6).map(|i| vr(Key::EstX(i))).collect();
    let outs = real_outputs(Model::Filter);
    let slots: Vec<(usize, Slot)> = sc
        .channels
        .iter()
        .enumerate()
        .map(|(c, spec)| (c, Slot::of(spec.channel).unwrap()))
        .collect();
    let make = || {
        let i = Inst::new(Model::Filter);
        let (n, f) = (CString::new(name).unwrap(), CString::new(filter).unwrap());
        let seed_i = seed as i32;
        // SAFETY: our instance; one value per call.
        unsafe {
            assert_eq!(fmi2SetString(i.c, &vr(Key::Scenario), 1, &n.as_ptr()), 0);
            assert_eq!(fmi2SetString(i.c, &vr(Key::Filter), 1, &f.as_ptr()), 0);
            assert_eq!(fmi2SetInteger(i.c, &vr(Key::Seed), 1, &seed_i), 0);
        }
        i.init();
        i
    };
    // One step: the bank and the pending epoch as inputs; returns every real output.
    let step = |i: &Inst, k: usize, bank: f64| {
        let e = epochs[k].as_ref();
        // SAFETY: our instance; one value per call.
        unsafe {
            assert_eq!(fmi2SetReal(i.c, &vr(Key::Bank), 1, &bank), 0);
            let on = e.is_some() as c_int;
            assert_eq!(fmi2SetBoolean(i.c, &vr(Key::MeasEpoch), 1, &on), 0);
            if let Some(e) = e {
                assert_eq!(fmi2SetReal(i.c, &vr(Key::MeasTime), 1, &e.t), 0);
                for &(c, s) in &slots {
                    let (z, ok) = (e.values[c].unwrap_or(0.0), e.values[c].is_some());
                    let ok = ok as c_int;
                    assert_eq!(fmi2SetReal(i.c, &vr(Key::Meas(s)), 1, &z), 0);
                    assert_eq!(fmi2SetBoolean(i.c, &vr(Key::MeasValid(s)), 1, &ok), 0);
                }
            }
            assert!(fmi2DoStep(i.c, k as f64, 1.0, 0) <= 1, "{}", i.last());
        }
        i.reals(&outs)
    };
    let bits = |x: &[f64]| x.iter().map(|v| v.to_bits()).collect::<Vec<_>>();
    let kind = FilterKind::parse(filter).unwrap();
    let mut nav = Navigator::for_seed(&sc, kind, seed, false).unwrap();
    let a = make();
    let mut st: *mut c_void = std::ptr::null_mut();
    for (k, e) in epochs.iter().enumerate().take(100) {
        step(&a, k, bank_of(k));
        nav.do_step(k as f64, 1.0, bank_of(k), e.as_ref()).unwrap();
        assert_eq!(a.reals(&est), bits(&nav.estimate().x[..6]), "step {k}");
        if k == 59 {
            // SAFETY: our instance.
            unsafe { assert_eq!(fmi2GetFMUstate(a.c, &mut st), 0) };
        }
    }
    // Left at bank 0 the filter FMU ends elsewhere.
    let zero = make();
    for k in 0..100 {
        step(&zero, k, 0.0);
    }
    assert_ne!(zero.reals(&est), a.reals(&est));
    // Restored after step 59, the bank log replays: the same outputs as the first pass.
    let mut st2: *mut c_void = std::ptr::null_mut();
    let b = Inst::new(Model::Filter);
    // SAFETY: our instances and states.
    unsafe {
        let mut size = 0usize;
        assert_eq!(fmi2SerializedFMUstateSize(a.c, st, &mut size), 0);
        let mut buf = vec![0u8; size];
        assert_eq!(fmi2SerializeFMUstate(a.c, st, buf.as_mut_ptr(), size), 0);
        assert_eq!(
            fmi2DeSerializeFMUstate(b.c, buf.as_ptr(), buf.len(), &mut st2),
            0
        );
        assert_eq!(fmi2SetFMUstate(b.c, st2), 0, "{}", b.last());
        assert_eq!(fmi2SetFMUstate(a.c, st), 0, "{}", a.last());
    }
    let again: Vec<_> = (60..100).map(|k| step(&a, k, bank_of(k))).collect();
    let restored: Vec<_> = (60..100).map(|k| step(&b, k, bank_of(k))).collect();
    assert_eq!(again, restored);
    assert_eq!(a.reals(&est), bits(&nav.estimate().x[..6]));
    // SAFETY: our instances and states.
    unsafe {
        assert_eq!(fmi2FreeFMUstate(a.c, &mut st), 0);
        assert_eq!(fmi2FreeFMUstate(b.c, &mut st2), 0);
    }
}
