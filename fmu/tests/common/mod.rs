//! Helpers of the C-API tests: a logger that records messages, and an instance driven through
//! the exported fmi2 functions by variable key.
#![allow(dead_code)]

use entrynav_fmu::ffi::*;
use entrynav_fmu::guid_of;
use entrynav_fmu::vars::{Key, Model, variables};
use std::ffi::{CStr, CString, c_char, c_int, c_void};
use std::sync::Mutex;

/// Messages an instance logged: (status, category, text).
pub type Log = Mutex<Vec<(i32, String, String)>>;

extern "C" fn logger(
    env: *mut c_void,
    _name: *const c_char,
    status: c_int,
    cat: *const c_char,
    msg: *const c_char,
) {
    // SAFETY: env is the test's `Log`; cat and msg are C strings from the FMU.
    let (log, cat, text) = unsafe {
        (
            &*(env as *const Log),
            CStr::from_ptr(cat).to_string_lossy(),
            CStr::from_ptr(msg).to_string_lossy(),
        )
    };
    log.lock()
        .unwrap()
        .push((status, cat.into_owned(), text.into_owned()));
}

/// Callbacks that log into `log`.
pub fn callbacks(log: &Log) -> CallbackFunctions {
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

/// An instance of a generic model through the C API.
pub struct Inst {
    pub c: *mut c_void,
    pub model: Model,
    _cb: Box<CallbackFunctions>,
    pub log: Box<Log>,
}

impl Inst {
    /// Without a resource location (built-in scenarios only).
    pub fn new(model: Model) -> Inst {
        Inst::with(model, None, false)
    }

    /// With the resource location `resources` and logging on or off.
    pub fn with(model: Model, resources: Option<&str>, logging_on: bool) -> Inst {
        let log: Box<Log> = Box::new(Mutex::new(Vec::new()));
        let cb = Box::new(callbacks(&log));
        let name = CString::new("test").unwrap();
        let guid = CString::new(guid_of(model)).unwrap();
        let res = resources.map(|r| CString::new(r).unwrap());
        let res_ptr = res.as_ref().map(|r| r.as_ptr()).unwrap_or(std::ptr::null());
        // SAFETY: valid arguments.
        let c = unsafe {
            fmi2Instantiate(
                name.as_ptr(),
                1,
                guid.as_ptr(),
                res_ptr,
                &*cb,
                0,
                logging_on as c_int,
            )
        };
        assert!(!c.is_null());
        Inst {
            c,
            model,
            _cb: cb,
            log,
        }
    }

    pub fn vr(&self, key: Key) -> u32 {
        variables(self.model)
            .iter()
            .find(|v| v.key == key)
            .unwrap()
            .vr
    }

    pub fn messages(&self) -> Vec<(i32, String, String)> {
        self.log.lock().unwrap().clone()
    }

    pub fn last(&self) -> String {
        self.messages()
            .last()
            .map(|m| m.2.clone())
            .unwrap_or_default()
    }

    pub fn set_string(&self, key: Key, s: &str) -> i32 {
        let c = CString::new(s).unwrap();
        // SAFETY: our instance; one reference and one C string.
        unsafe { fmi2SetString(self.c, &self.vr(key), 1, &c.as_ptr()) }
    }

    pub fn set_bool(&self, key: Key, b: bool) -> i32 {
        // SAFETY: our instance; one reference and one value.
        unsafe { fmi2SetBoolean(self.c, &self.vr(key), 1, &(b as c_int)) }
    }

    pub fn set_real(&self, key: Key, x: f64) -> i32 {
        // SAFETY: our instance; one reference and one value.
        unsafe { fmi2SetReal(self.c, &self.vr(key), 1, &x) }
    }

    pub fn set_int(&self, key: Key, x: i32) -> i32 {
        // SAFETY: our instance; one reference and one value.
        unsafe { fmi2SetInteger(self.c, &self.vr(key), 1, &x) }
    }

    pub fn boolean(&self, key: Key) -> bool {
        let mut x = -1;
        // SAFETY: our instance; one reference and room for one value.
        assert_eq!(
            unsafe { fmi2GetBoolean(self.c, &self.vr(key), 1, &mut x) },
            0,
            "{}",
            self.last()
        );
        x != 0
    }

    pub fn real(&self, key: Key) -> f64 {
        let mut x = f64::NAN;
        // SAFETY: our instance; one reference and room for one value.
        assert_eq!(
            unsafe { fmi2GetReal(self.c, &self.vr(key), 1, &mut x) },
            0,
            "{}",
            self.last()
        );
        x
    }

    pub fn int(&self, key: Key) -> i32 {
        let mut x = -1;
        // SAFETY: our instance; one reference and room for one value.
        assert_eq!(
            unsafe { fmi2GetInteger(self.c, &self.vr(key), 1, &mut x) },
            0,
            "{}",
            self.last()
        );
        x
    }

    /// SetupExperiment (no stop time), Enter and Exit initialisation: the three statuses.
    pub fn init(&self) -> [i32; 3] {
        // SAFETY: our instance.
        unsafe {
            [
                fmi2SetupExperiment(self.c, 0, 0.0, 0.0, 0, 0.0),
                fmi2EnterInitializationMode(self.c),
                fmi2ExitInitializationMode(self.c),
            ]
        }
    }

    pub fn step(&self, t: f64, h: f64) -> i32 {
        // SAFETY: our instance.
        unsafe { fmi2DoStep(self.c, t, h, 0) }
    }
}

impl Drop for Inst {
    fn drop(&mut self) {
        // SAFETY: our instance.
        unsafe { fmi2FreeInstance(self.c) };
    }
}
