//! [`Slave`]: one FMI 2.0 co-simulation instance of a loaded FMU, with its message buffer; the
//! [`FmiInstance`] calls, and setting one variable of the table.

use crate::api::{Api, Callbacks, Comp, Log, host_logger};
use crate::error::{HostError, Result};
use crate::instance::{FmiInstance, FmuState, Message, StepAnswer};
use entrynav_fmu::vars::{Value, Var};
use std::ffi::{CString, c_char, c_int, c_void};
use std::sync::Arc;

/// One FMI 2.0 instance through the host.
pub struct Slave {
    /// The library's functions.
    pub api: Arc<Api>,
    /// The instance (null for [`Slave::null`]).
    pub c: Comp,
    /// Messages the instance logged.
    pub log: Box<Log>,
    _callbacks: Box<Callbacks>,
    freed: bool,
}

impl Slave {
    /// Instantiate co-simulation slave `name` of the library's model with `guid` and the resource
    /// URI `resources`, logging off (errors and warnings are logged all the same).
    pub fn new(api: &Arc<Api>, name: &str, guid: &str, resources: &str) -> Result<Slave> {
        Slave::instantiate(api, name, guid, resources, false)
    }

    /// [`Slave::new`] with debug logging on or off.
    pub fn instantiate(
        api: &Arc<Api>,
        name: &str,
        guid: &str,
        resources: &str,
        logging_on: bool,
    ) -> Result<Slave> {
        let log: Box<Log> = Box::new(Log::new(Vec::new()));
        let callbacks = Box::new(Callbacks {
            logger: Some(host_logger),
            allocate: None,
            free: None,
            step_finished: None,
            env: &*log as *const Log as *mut c_void,
        });
        let (n, g, r) = (
            CString::new(name)?,
            CString::new(guid)?,
            CString::new(resources)?,
        );
        // SAFETY: valid C strings and callbacks that outlive the instance.
        let c = unsafe {
            (api.fmi2Instantiate)(
                n.as_ptr(),
                1,
                g.as_ptr(),
                r.as_ptr(),
                &*callbacks,
                0,
                logging_on as c_int,
            )
        };
        let s = Slave {
            api: Arc::clone(api),
            c,
            log,
            _callbacks: callbacks,
            freed: false,
        };
        if c.is_null() {
            return Err(HostError::Instantiate(s.messages()));
        }
        Ok(s)
    }

    /// A slave whose instance is null: every call must be refused (and freeing it is harmless).
    pub fn null(api: &Arc<Api>) -> Slave {
        Slave {
            api: Arc::clone(api),
            c: std::ptr::null_mut(),
            log: Box::default(),
            _callbacks: Box::new(Callbacks {
                logger: None,
                allocate: None,
                free: None,
                step_finished: None,
                env: std::ptr::null_mut(),
            }),
            freed: false,
        }
    }

    /// The messages logged so far.
    pub fn messages(&self) -> Vec<Message> {
        self.log.lock().map(|l| l.clone()).unwrap_or_default()
    }

    /// Set one variable; returns the fmi2Status.
    pub fn set(&self, v: &Var, val: &Value) -> i32 {
        let vr = [v.vr];
        // SAFETY: one reference and one value of the right type.
        unsafe {
            match val {
                Value::Real(x) => (self.api.fmi2SetReal)(self.c, vr.as_ptr(), 1, x),
                Value::Integer(x) => (self.api.fmi2SetInteger)(self.c, vr.as_ptr(), 1, x),
                Value::Boolean(x) => {
                    (self.api.fmi2SetBoolean)(self.c, vr.as_ptr(), 1, &(*x as c_int))
                }
                Value::String(s) => {
                    let cs = CString::new(s.as_str()).unwrap_or_default();
                    (self.api.fmi2SetString)(self.c, vr.as_ptr(), 1, &cs.as_ptr())
                }
            }
        }
    }
}

impl Drop for Slave {
    fn drop(&mut self) {
        self.free();
    }
}

impl FmiInstance for Slave {
    const PREFIX: &'static str = "fmi2";
    type Boolean = c_int;

    fn handle(&self) -> *mut c_void {
        self.c
    }

    fn take_messages(&self) -> Vec<Message> {
        self.log
            .lock()
            .map(|mut l| std::mem::take(&mut *l))
            .unwrap_or_default()
    }

    fn free(&mut self) {
        if !self.freed {
            // SAFETY: our instance (or null).
            unsafe { (self.api.fmi2FreeInstance)(self.c) };
            self.freed = true;
        }
    }

    fn enter_initialization_mode(
        &self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> i32 {
        let a = &self.api;
        // SAFETY: our instance.
        unsafe {
            let r = (a.fmi2SetupExperiment)(
                self.c,
                tolerance.is_some() as c_int,
                tolerance.unwrap_or(0.0),
                start,
                stop.is_some() as c_int,
                stop.unwrap_or(0.0),
            );
            match r {
                0 => (a.fmi2EnterInitializationMode)(self.c),
                _ => r,
            }
        }
    }

    fn exit_initialization_mode(&self) -> i32 {
        // SAFETY: our instance.
        unsafe { (self.api.fmi2ExitInitializationMode)(self.c) }
    }

    fn do_step(&self, t: f64, h: f64, no_set_fmu_state_prior: bool, _flags: bool) -> StepAnswer {
        // SAFETY: our instance.
        let status =
            unsafe { (self.api.fmi2DoStep)(self.c, t, h, no_set_fmu_state_prior as c_int) };
        StepAnswer {
            status,
            flags: None,
            last_successful_time: None,
        }
    }

    fn terminate(&self) -> i32 {
        // SAFETY: our instance.
        unsafe { (self.api.fmi2Terminate)(self.c) }
    }

    fn reset(&self) -> i32 {
        // SAFETY: our instance.
        unsafe { (self.api.fmi2Reset)(self.c) }
    }

    unsafe fn set_debug_logging(
        &self,
        on: c_int,
        n: usize,
        categories: *const *const c_char,
    ) -> i32 {
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi2SetDebugLogging)(self.c, on, n, categories) }
    }

    unsafe fn get_float64(
        &self,
        vrs: *const u32,
        nvr: usize,
        values: *mut f64,
        n_values: usize,
    ) -> i32 {
        debug_assert_eq!(nvr, n_values, "FMI 2.0 has one value per reference");
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi2GetReal)(self.c, vrs, nvr, values) }
    }

    unsafe fn set_float64(
        &self,
        vrs: *const u32,
        nvr: usize,
        values: *const f64,
        n_values: usize,
    ) -> i32 {
        debug_assert_eq!(nvr, n_values, "FMI 2.0 has one value per reference");
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi2SetReal)(self.c, vrs, nvr, values) }
    }

    unsafe fn get_int32(
        &self,
        vrs: *const u32,
        nvr: usize,
        values: *mut i32,
        n_values: usize,
    ) -> i32 {
        debug_assert_eq!(nvr, n_values, "FMI 2.0 has one value per reference");
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi2GetInteger)(self.c, vrs, nvr, values) }
    }

    unsafe fn set_int32(
        &self,
        vrs: *const u32,
        nvr: usize,
        values: *const i32,
        n_values: usize,
    ) -> i32 {
        debug_assert_eq!(nvr, n_values, "FMI 2.0 has one value per reference");
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi2SetInteger)(self.c, vrs, nvr, values) }
    }

    unsafe fn get_boolean(
        &self,
        vrs: *const u32,
        nvr: usize,
        values: *mut c_int,
        n_values: usize,
    ) -> i32 {
        debug_assert_eq!(nvr, n_values, "FMI 2.0 has one value per reference");
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi2GetBoolean)(self.c, vrs, nvr, values) }
    }

    unsafe fn set_boolean(
        &self,
        vrs: *const u32,
        nvr: usize,
        values: *const c_int,
        n_values: usize,
    ) -> i32 {
        debug_assert_eq!(nvr, n_values, "FMI 2.0 has one value per reference");
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi2SetBoolean)(self.c, vrs, nvr, values) }
    }

    unsafe fn get_string(
        &self,
        vrs: *const u32,
        nvr: usize,
        values: *mut *const c_char,
        n_values: usize,
    ) -> i32 {
        debug_assert_eq!(nvr, n_values, "FMI 2.0 has one value per reference");
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi2GetString)(self.c, vrs, nvr, values) }
    }

    unsafe fn set_string(
        &self,
        vrs: *const u32,
        nvr: usize,
        values: *const *const c_char,
        n_values: usize,
    ) -> i32 {
        debug_assert_eq!(nvr, n_values, "FMI 2.0 has one value per reference");
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi2SetString)(self.c, vrs, nvr, values) }
    }

    unsafe fn get_fmu_state(&self, state: *mut FmuState) -> i32 {
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi2GetFMUstate)(self.c, state) }
    }

    unsafe fn set_fmu_state(&self, state: FmuState) -> i32 {
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi2SetFMUstate)(self.c, state) }
    }

    unsafe fn free_fmu_state(&self, state: *mut FmuState) -> i32 {
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi2FreeFMUstate)(self.c, state) }
    }

    unsafe fn serialized_fmu_state_size(&self, state: FmuState, size: *mut usize) -> i32 {
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi2SerializedFMUstateSize)(self.c, state, size) }
    }

    unsafe fn serialize_fmu_state(&self, state: FmuState, bytes: *mut u8, size: usize) -> i32 {
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi2SerializeFMUstate)(self.c, state, bytes, size) }
    }

    unsafe fn deserialize_fmu_state(
        &self,
        bytes: *const u8,
        size: usize,
        state: *mut FmuState,
    ) -> i32 {
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi2DeSerializeFMUstate)(self.c, bytes, size, state) }
    }
}
