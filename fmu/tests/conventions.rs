//! FMI conventions through the C API: the status kinds, the error state after a failed
//! initialisation, a logged reason for a call on a busy instance, the bounds on every size-like
//! argument, and a `scenario` parameter that cannot read or disclose host files.

mod common;

use common::{Inst, callbacks};
use entrynav_fmu::ffi::*;
use entrynav_fmu::limits::{
    MAX_CATEGORIES, MAX_SNAPSHOTS, MAX_STATE_BYTES, MAX_STRING_BYTES, MAX_STRING_REFS,
    MAX_VALUE_REFS,
};
use entrynav_fmu::vars::{Key, Model};
use std::ffi::{CString, c_char, c_int, c_void};
use std::sync::Mutex;

#[test]
fn status_kinds_invalid_is_error_unavailable_is_discard() {
    let i = Inst::new(Model::Combined);
    assert_eq!(i.set_string(Key::Filter, "ekf"), 0);
    assert_eq!(i.init(), [0, 0, 0]);
    assert_eq!(i.step(0.0, 2.0), 0);
    let (mut st, mut x, mut n, mut b, mut s) = (
        0 as c_int,
        0.0,
        0 as c_int,
        1 as c_int,
        std::ptr::null::<c_char>(),
    );
    // SAFETY: our instance and one value of each function's type.
    unsafe {
        assert_eq!(fmi2GetRealStatus(i.c, 2, &mut x), 0);
        assert_eq!(x, 2.0);
        assert_eq!(fmi2GetBooleanStatus(i.c, 3, &mut b), 0);
        assert_eq!(b, 0);
        let before = i.messages().len();
        assert_eq!(
            fmi2GetStatus(i.c, 0, &mut st),
            2,
            "no asynchronous step: fmi2Discard"
        );
        assert_eq!(fmi2GetStringStatus(i.c, 1, &mut s), 2);
        for k in [-1, 4, 7, 99] {
            assert_eq!(
                fmi2GetStatus(i.c, k, &mut st),
                3,
                "kind {k} is not an fmi2StatusKind"
            );
            assert_eq!(fmi2GetRealStatus(i.c, k, &mut x), 3);
        }
        assert_eq!(
            fmi2GetRealStatus(i.c, 3, &mut x),
            3,
            "fmi2Terminated is a Boolean kind"
        );
        assert_eq!(fmi2GetBooleanStatus(i.c, 2, &mut b), 3);
        assert_eq!(
            fmi2GetIntegerStatus(i.c, 2, &mut n),
            3,
            "FMI 2.0 has no Integer kind"
        );
        let msgs = i.messages();
        assert_eq!(
            msgs.len(),
            before + 13,
            "one logged reason per call: {msgs:?}"
        );
        assert_eq!(msgs[before].1, "logStatusDiscard");
        assert!(
            msgs[before + 2].2.contains("not an fmi2StatusKind"),
            "{msgs:?}"
        );
        assert!(
            msgs.last().unwrap().2.contains("fmi2GetRealStatus"),
            "{msgs:?}"
        );
    }
}

#[test]
fn a_failed_initialisation_is_the_error_state_until_reset() {
    let i = Inst::new(Model::Combined);
    // DCIFAIF fuses one local filter per beacon; msl-airdata has no radio beacons.
    assert_eq!(i.set_string(Key::Scenario, "msl-airdata"), 0);
    assert_eq!(i.set_string(Key::Filter, "dcifaif"), 0);
    assert_eq!(i.init(), [0, 0, 3]);
    assert!(
        i.last().contains("does not fit") && i.last().contains("error state"),
        "{}",
        i.last()
    );
    assert_eq!(i.set_string(Key::Filter, "ekf"), 3);
    assert!(i.last().contains("Illegal call sequence"), "{}", i.last());
    // SAFETY: our instance.
    unsafe {
        assert_eq!(fmi2ExitInitializationMode(i.c), 3);
        assert_eq!(fmi2Terminate(i.c), 3);
        assert_eq!(fmi2Reset(i.c), 0);
    }
    assert_eq!(i.set_string(Key::Scenario, "msl-airdata"), 0);
    assert_eq!(i.set_string(Key::Filter, "ekf"), 0);
    assert_eq!(i.init(), [0, 0, 0], "{}", i.last());
}

/// A call from a second thread while the first is inside a call: the first thread's logger (it
/// runs inside fmi2ExitInitializationMode) makes the second call and waits for it.
#[test]
fn a_call_on_a_busy_instance_is_refused_with_a_logged_reason() {
    static COMPONENT: Mutex<usize> = Mutex::new(0);
    static ANSWER: Mutex<Option<i32>> = Mutex::new(None);
    type Log = Mutex<Vec<String>>;
    extern "C" fn logger(
        env: *mut c_void,
        _n: *const c_char,
        _s: c_int,
        _c: *const c_char,
        m: *const c_char,
    ) {
        // SAFETY: env is the test's Log, m a C string.
        let (log, msg) = unsafe {
            (
                &*(env as *const Log),
                std::ffi::CStr::from_ptr(m).to_string_lossy().into_owned(),
            )
        };
        let c = *COMPONENT.lock().unwrap();
        log.lock().unwrap().push(msg.clone());
        if msg == "initialised" && c != 0 {
            let other = std::thread::spawn(move || {
                let mut x = 0.0;
                let vr = 0u32;
                // SAFETY: the instance is alive (its first call is still running).
                unsafe { fmi2GetReal(c as *mut c_void, &vr, 1, &mut x) }
            });
            *ANSWER.lock().unwrap() = other.join().ok();
        }
    }
    let log: Box<Log> = Box::new(Mutex::new(Vec::new()));
    let mut cb = callbacks(&Mutex::new(Vec::new()));
    // SAFETY: as in common::callbacks.
    cb.logger = Some(unsafe {
        std::mem::transmute::<
            extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char),
            LoggerFn,
        >(logger)
    });
    cb.component_environment = &*log as *const Log as *mut c_void;
    let (name, guid) = (
        CString::new("busy").unwrap(),
        CString::new(entrynav_fmu::guid_of(Model::Truth)).unwrap(),
    );
    // SAFETY: valid arguments; logging on so that the initialisation logs an event.
    let c =
        unsafe { fmi2Instantiate(name.as_ptr(), 1, guid.as_ptr(), std::ptr::null(), &cb, 0, 1) };
    assert!(!c.is_null());
    *COMPONENT.lock().unwrap() = c as usize;
    // SAFETY: our instance.
    unsafe {
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), 0);
        assert_eq!(fmi2EnterInitializationMode(c), 0);
        assert_eq!(fmi2ExitInitializationMode(c), 0);
        *COMPONENT.lock().unwrap() = 0;
        fmi2FreeInstance(c);
    }
    assert_eq!(*ANSWER.lock().unwrap(), Some(3));
    let msgs = log.lock().unwrap().clone();
    assert!(
        msgs.iter()
            .any(|m| m.starts_with("fmi2GetReal: the instance is busy")),
        "{msgs:?}"
    );
}

#[test]
fn every_size_like_argument_is_bounded_before_it_is_used() {
    let i = Inst::new(Model::Combined);
    assert_eq!(i.init(), [0, 0, 0]);
    let big = vec![i.vr(Key::Bank); MAX_VALUE_REFS + 1];
    let mut out = vec![0.0; MAX_VALUE_REFS + 1];
    let long = CString::new("x".repeat(MAX_STRING_BYTES + 1)).unwrap();
    let cats: Vec<CString> = (0..=MAX_CATEGORIES)
        .map(|_| CString::new("logAll").unwrap())
        .collect();
    let cat_ptrs: Vec<*const c_char> = cats.iter().map(|c| c.as_ptr()).collect();
    // SAFETY: our instance; every buffer has the length passed, except the over-the-bound counts,
    // which must be refused before anything is read.
    unsafe {
        assert_eq!(
            fmi2GetReal(i.c, big.as_ptr(), MAX_VALUE_REFS + 1, out.as_mut_ptr()),
            3
        );
        assert_eq!(
            fmi2GetReal(i.c, big.as_ptr(), usize::MAX / 8, out.as_mut_ptr()),
            3
        );
        assert_eq!(
            fmi2GetReal(i.c, big.as_ptr(), MAX_VALUE_REFS, out.as_mut_ptr()),
            0,
            "{}",
            i.last()
        );
        let strs = vec![i.vr(Key::Scenario); MAX_STRING_REFS + 1];
        let mut ptrs = vec![std::ptr::null::<c_char>(); MAX_STRING_REFS + 1];
        assert_eq!(
            fmi2GetString(i.c, strs.as_ptr(), MAX_STRING_REFS + 1, ptrs.as_mut_ptr()),
            3
        );
        assert_eq!(
            fmi2GetString(i.c, strs.as_ptr(), MAX_STRING_REFS, ptrs.as_mut_ptr()),
            0
        );
        assert_eq!(fmi2SetString(i.c, &i.vr(Key::Filter), 1, &long.as_ptr()), 3);
        assert!(i.last().contains("longer than 4096 bytes"), "{}", i.last());
        assert_eq!(
            fmi2SetDebugLogging(i.c, 1, cat_ptrs.len(), cat_ptrs.as_ptr()),
            3
        );
        assert_eq!(
            fmi2SetDebugLogging(i.c, 1, MAX_CATEGORIES, cat_ptrs.as_ptr()),
            0
        );
        let mut q: *mut c_void = std::ptr::null_mut();
        let tiny = [0u8; 8];
        assert_eq!(
            fmi2DeSerializeFMUstate(i.c, tiny.as_ptr(), MAX_STATE_BYTES + 1, &mut q),
            3
        );
        assert!(q.is_null());
        let mut held = Vec::new();
        for k in 0..=MAX_SNAPSHOTS {
            let mut p: *mut c_void = std::ptr::null_mut();
            let r = fmi2GetFMUstate(i.c, &mut p);
            assert_eq!(r, if k < MAX_SNAPSHOTS { 0 } else { 3 }, "state {k}");
            held.push(p);
        }
        for mut p in held {
            assert_eq!(fmi2FreeFMUstate(i.c, &mut p), 0);
        }
        let log = Mutex::new(Vec::new());
        let cb = callbacks(&log);
        let guid = CString::new(entrynav_fmu::guid_of(Model::Combined)).unwrap();
        assert!(
            fmi2Instantiate(long.as_ptr(), 1, guid.as_ptr(), std::ptr::null(), &cb, 0, 0).is_null()
        );
        let long_guid = CString::new("{".repeat(300)).unwrap();
        assert!(
            fmi2Instantiate(
                guid.as_ptr(),
                1,
                long_guid.as_ptr(),
                std::ptr::null(),
                &cb,
                0,
                0
            )
            .is_null()
        );
        assert_eq!(log.lock().unwrap().len(), 2);
    }
}

/// A master that steps forever with inputs that change at every step: the replay log stops at its
/// bound, fmi2GetFMUstate refuses from then on, the run goes on, and fmi2Reset starts afresh.
#[test]
fn the_replay_log_is_bounded() {
    let i = Inst::new(Model::Filter);
    assert_eq!(i.set_string(Key::Filter, "ekf"), 0);
    assert_eq!(i.init(), [0, 0, 0]);
    let mut p: *mut c_void = std::ptr::null_mut();
    let mut k = 0usize;
    // About 224 bytes per step when every input changes: the log is full after ~75,000 steps.
    while !i.messages().iter().any(|m| m.2.contains("replay log")) {
        assert!(k < 200_000, "the log never filled");
        assert_eq!(i.set_real(Key::Bank, (k % 7) as f64 * 0.01), 0);
        assert_eq!(i.set_real(Key::MeasTime, k as f64 * 1e-6), 0);
        assert_eq!(i.step(k as f64, 1.0), 0, "{}", i.last());
        k += 1;
    }
    assert!(
        k as f64 * 207.0 > (MAX_STATE_BYTES / 2) as f64,
        "full after only {k} steps"
    );
    // SAFETY: our instance.
    unsafe {
        assert_eq!(fmi2GetFMUstate(i.c, &mut p), 3);
        assert!(i.last().contains("outgrew"), "{}", i.last());
        assert_eq!(i.step(k as f64, 1.0), 0, "the run goes on");
        assert_eq!(fmi2Reset(i.c), 0);
        assert_eq!(fmi2GetFMUstate(i.c, &mut p), 0);
        assert_eq!(fmi2FreeFMUstate(i.c, &mut p), 0);
    }
}

#[test]
fn the_scenario_parameter_cannot_read_or_disclose_host_files() {
    let base = std::env::temp_dir().join(format!("entrynav-scenario-{}", std::process::id()));
    let res = base.join("resources");
    std::fs::create_dir_all(&res).unwrap();
    let secret = base.join("secret.txt");
    std::fs::write(
        &secret,
        "root:x:0:0:root:/root:/bin/bash\ntoken = \"s3cr3t\"\n",
    )
    .unwrap();
    std::os::unix::fs::symlink(&secret, res.join("link.toml")).unwrap();
    std::fs::write(
        res.join("broken.toml"),
        "name = \"x\"\nduration = [s3cr3t\n",
    )
    .unwrap();
    let uri = format!("file://{}", res.display());
    let secret_path = secret.display().to_string();
    let cases: [(&str, bool, &str); 8] = [
        (&secret_path, false, "allow_external_files = true"),
        ("../secret.txt", false, "allow_external_files = true"),
        ("link.toml", false, "allow_external_files = true"),
        ("missing.toml", false, "cannot be read"),
        // A mistyped built-in gets the list and the nearest name.
        ("msl-airdta", false, "did you mean 'msl-airdata'?"),
        ("broken.toml", false, "line 2"),
        (&secret_path, true, "TOML parse error at line 1"),
        ("/dev/zero", true, "not a regular file"),
    ];
    for (name, allow, expected) in cases {
        let i = Inst::with(Model::Truth, Some(&uri), false);
        assert_eq!(i.set_string(Key::Scenario, name), 0);
        assert_eq!(i.set_bool(Key::AllowExternalFiles, allow), 0);
        assert_eq!(i.init()[2], 3, "{name} (allow {allow}) must not load");
        let msg = i.last();
        assert!(msg.contains(expected), "{name} (allow {allow}): {msg}");
        assert!(
            !msg.contains("root:x") && !msg.contains("s3cr3t"),
            "{name} discloses: {msg}"
        );
    }
    // A scenario in resources/ loads.
    let text = entrynav::scenario::builtin_toml("msl-pressure").unwrap();
    std::fs::write(res.join("mine.toml"), text).unwrap();
    let i = Inst::with(Model::Truth, Some(&uri), false);
    assert_eq!(i.set_string(Key::Scenario, "./mine.toml"), 0);
    assert_eq!(i.init(), [0, 0, 0], "{}", i.last());
    // A scenario whose run needs 4 million truth steps is over the bound of a run (scenario
    // validation refuses it; the FMU's own MAX_RUN_TRUTH_STEPS stays behind it).
    let long = text.replace("truth_step_s = 0.1", "truth_step_s = 0.0001");
    assert_ne!(long, text);
    std::fs::write(res.join("long.toml"), long).unwrap();
    let i = Inst::with(Model::Truth, Some(&uri), false);
    assert_eq!(i.set_string(Key::Scenario, "long.toml"), 0);
    assert_eq!(i.init()[2], 3);
    let msg = i.last();
    assert!(
        msg.contains("timing.truth_step_s = 0.0001") && msg.contains("at most 1e6 truth steps"),
        "{msg}"
    );
    std::fs::remove_dir_all(&base).unwrap();
}
