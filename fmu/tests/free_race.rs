//! `fmi2FreeInstance` while another thread is calling the same instance (which FMI 2.0 forbids,
//! and a master may still do): no crash, no use after free, no leak, and every call after the
//! free is refused. Run under valgrind with fewer rounds (`FREE_RACE_ROUNDS`) to see that no
//! freed memory is read.

mod common;

use common::callbacks;
use entrynav_fmu::ffi::*;
use entrynav_fmu::guid_of;
use entrynav_fmu::vars::{Key, Model, variables};
use std::ffi::{CString, c_char, c_int, c_void};
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

/// The tests of this file count live instances, so they run one at a time.
static SERIAL: Mutex<()> = Mutex::new(());

fn rounds() -> usize {
    std::env::var("FREE_RACE_ROUNDS")
        .ok()
        .and_then(|r| r.parse().ok())
        .unwrap_or(300)
}

/// An initialised truth instance (a token, as the master holds it).
fn instantiate(cb: &CallbackFunctions, logging_on: bool) -> usize {
    let (name, guid) = (
        CString::new("race").unwrap(),
        CString::new(guid_of(Model::Truth)).unwrap(),
    );
    // SAFETY: valid arguments.
    let c = unsafe {
        fmi2Instantiate(
            name.as_ptr(),
            1,
            guid.as_ptr(),
            std::ptr::null(),
            cb,
            0,
            logging_on as c_int,
        )
    };
    assert!(!c.is_null());
    c as usize
}

fn altitude_vr() -> u32 {
    variables(Model::Truth)
        .iter()
        .find(|v| v.key == Key::TruthAltitude)
        .unwrap()
        .vr
}

#[test]
fn freeing_while_another_thread_hammers_the_instance_is_safe() {
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let log = Mutex::new(Vec::new());
    let cb = callbacks(&log);
    let before = live_instances();
    let vr = altitude_vr();
    for round in 0..rounds() {
        let c = instantiate(&cb, false);
        // SAFETY: our instance.
        unsafe {
            assert_eq!(
                fmi2SetupExperiment(c as *mut c_void, 0, 0.0, 0.0, 0, 0.0),
                0
            );
            assert_eq!(fmi2EnterInitializationMode(c as *mut c_void), 0);
            assert_eq!(fmi2ExitInitializationMode(c as *mut c_void), 0);
        }
        let calls = AtomicUsize::new(0);
        let (freeing, freed) = (AtomicBool::new(false), AtomicBool::new(false));
        std::thread::scope(|s| {
            s.spawn(|| {
                let comp = c as *mut c_void;
                let (mut t, mut x) = (0.0, 0.0);
                while !freed.load(Ordering::Acquire) {
                    // SAFETY: a token of this test (live or freed: both must be answered).
                    let got = unsafe { fmi2GetReal(comp, &vr, 1, &mut x) };
                    let step = match round % 2 {
                        0 => unsafe { fmi2DoStep(comp, t, 0.5, 0) },
                        _ => got,
                    };
                    for st in [got, step] {
                        assert!(st <= 1 || st == 3, "status {st}");
                        if st == 3 {
                            assert!(freeing.load(Ordering::Acquire), "refused before the free");
                        }
                    }
                    if step <= 1 {
                        t += 0.5;
                    }
                    calls.fetch_add(1, Ordering::Release);
                }
                // Every call after the free is refused.
                // SAFETY: a freed token.
                unsafe {
                    assert_eq!(fmi2GetReal(comp, &vr, 1, &mut x), 3);
                    assert_eq!(fmi2DoStep(comp, t, 0.5, 0), 3);
                    assert_eq!(fmi2Reset(comp), 3);
                }
            });
            s.spawn(|| {
                // Free after a varying number of the other thread's calls, often mid-call.
                while calls.load(Ordering::Acquire) < round % 7 {
                    std::hint::spin_loop();
                }
                freeing.store(true, Ordering::Release);
                // SAFETY: our instance, freed once.
                unsafe { fmi2FreeInstance(c as *mut c_void) };
                freed.store(true, Ordering::Release);
            });
        });
        // SAFETY: a second free of the same token is ignored.
        unsafe { fmi2FreeInstance(c as *mut c_void) };
        assert_eq!(
            live_instances(),
            before,
            "round {round}: an instance leaked"
        );
    }
    let messages = log.lock().unwrap();
    assert!(
        messages.iter().all(|m| !m.1.contains("busy")),
        "fmi2FreeInstance does not wait for the lock: {messages:?}"
    );
}

/// The free comes while the other thread is inside a call (its logger runs in
/// fmi2ExitInitializationMode and frees the instance from a second thread): the call finishes,
/// the instance is gone afterwards, and nothing leaks or is refused as "busy".
#[test]
fn freeing_during_a_call_frees_when_the_call_returns() {
    static COMPONENT: AtomicUsize = AtomicUsize::new(0);
    extern "C" fn logger(
        env: *mut c_void,
        _n: *const c_char,
        _s: c_int,
        _c: *const c_char,
        m: *const c_char,
    ) {
        // SAFETY: env is the test's log, m a C string.
        let (log, msg) = unsafe {
            (
                &*(env as *const Mutex<Vec<String>>),
                std::ffi::CStr::from_ptr(m).to_string_lossy().into_owned(),
            )
        };
        log.lock().unwrap().push(msg.clone());
        let c = COMPONENT.swap(0, Ordering::AcqRel);
        if msg == "initialised" && c != 0 {
            // SAFETY: the instance is live; its first call is still running.
            std::thread::spawn(move || unsafe { fmi2FreeInstance(c as *mut c_void) })
                .join()
                .unwrap();
        }
    }
    let _serial = SERIAL.lock().unwrap_or_else(|e| e.into_inner());
    let log: Box<Mutex<Vec<String>>> = Box::new(Mutex::new(Vec::new()));
    let mut cb = callbacks(&Mutex::new(Vec::new()));
    // SAFETY: as in common::callbacks.
    cb.logger = Some(unsafe {
        std::mem::transmute::<
            extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char),
            LoggerFn,
        >(logger)
    });
    cb.component_environment = &*log as *const _ as *mut c_void;
    let before = live_instances();
    let c = instantiate(&cb, true) as *mut c_void;
    // SAFETY: our instance, freed from inside its own fmi2ExitInitializationMode.
    unsafe {
        assert_eq!(fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0), 0);
        assert_eq!(fmi2EnterInitializationMode(c), 0);
        COMPONENT.store(c as usize, Ordering::Release);
        assert_eq!(fmi2ExitInitializationMode(c), 0);
        assert_eq!(live_instances(), before);
        assert_eq!(fmi2DoStep(c, 0.0, 1.0, 0), 3);
        fmi2FreeInstance(c);
    }
    let msgs = log.lock().unwrap();
    assert!(msgs.iter().any(|m| m == "initialised"), "{msgs:?}");
    assert!(msgs.iter().all(|m| !m.contains("busy")), "{msgs:?}");
}
