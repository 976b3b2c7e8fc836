//! [`Slave3`]: one FMI 3.0 co-simulation instance of a loaded FMU, made by
//! `fmi3InstantiateCoSimulation` with the arguments of an [`Instantiate3`] and the host's log
//! callback; the [`FmiInstance`] calls.

use crate::api3::{Api3, Inst3, Log3, host_logger3};
use crate::instance::{FmiInstance, FmuState, Message, StepAnswer};
use std::ffi::{CStr, c_char, c_void};
use std::sync::Arc;

/// The arguments of `fmi3InstantiateCoSimulation` (a null pointer where `None`).
#[derive(Debug, Clone, Copy)]
pub struct Instantiate3<'s> {
    /// instanceName.
    pub name: Option<&'s CStr>,
    /// instantiationToken.
    pub token: Option<&'s CStr>,
    /// resourcePath.
    pub resources: Option<&'s CStr>,
    /// loggingOn.
    pub logging_on: bool,
    /// eventModeUsed.
    pub event_mode_used: bool,
    /// requiredIntermediateVariables.
    pub required: &'s [u32],
    /// Pass the host's log callback (else NULL: the FMU must log nothing and not crash).
    pub logger: bool,
}

impl<'s> Instantiate3<'s> {
    /// `name`, `token` and `resources`, logging off, no event mode, no intermediate variables,
    /// the host's logger.
    pub fn new(
        name: Option<&'s CStr>,
        token: Option<&'s CStr>,
        resources: Option<&'s CStr>,
    ) -> Instantiate3<'s> {
        Instantiate3 {
            name,
            token,
            resources,
            logging_on: false,
            event_mode_used: false,
            required: &[],
            logger: true,
        }
    }
}

/// One FMI 3.0 instance through the host (or a refused instantiation: a null handle).
pub struct Slave3 {
    /// The library's functions.
    pub api: Arc<Api3>,
    /// The instance.
    pub c: Inst3,
    log: Box<Log3>,
    freed: bool,
}

fn ptr(s: Option<&CStr>) -> *const c_char {
    s.map_or(std::ptr::null(), CStr::as_ptr)
}

impl Slave3 {
    /// `fmi3InstantiateCoSimulation` with `a` (the handle is null when the FMU refused).
    pub fn new(api: &Arc<Api3>, a: &Instantiate3) -> Slave3 {
        let log: Box<Log3> = Box::default();
        let env = &*log as *const Log3 as *mut c_void;
        // SAFETY: null or C strings, `required.len()` references, and a log buffer that outlives
        // the instance (freed before the box is dropped).
        let c = unsafe {
            (api.fmi3InstantiateCoSimulation)(
                ptr(a.name),
                ptr(a.token),
                ptr(a.resources),
                0,
                a.logging_on as u8,
                a.event_mode_used as u8,
                0,
                a.required.as_ptr(),
                a.required.len(),
                env,
                a.logger.then_some(host_logger3 as _),
                None,
            )
        };
        Slave3 {
            api: Arc::clone(api),
            c,
            log,
            freed: false,
        }
    }

    /// A slave whose instance is null: every call must be refused (and freeing it is harmless).
    pub fn null(api: &Arc<Api3>) -> Slave3 {
        Slave3 {
            api: Arc::clone(api),
            c: std::ptr::null_mut(),
            log: Box::default(),
            freed: false,
        }
    }
}

impl Drop for Slave3 {
    fn drop(&mut self) {
        self.free();
    }
}

impl FmiInstance for Slave3 {
    const PREFIX: &'static str = "fmi3";
    type Boolean = u8;

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
            // SAFETY: our instance, or null.
            unsafe { (self.api.fmi3FreeInstance)(self.c) };
            self.freed = true;
        }
    }

    fn enter_initialization_mode(
        &self,
        tolerance: Option<f64>,
        start: f64,
        stop: Option<f64>,
    ) -> i32 {
        // SAFETY: our instance.
        unsafe {
            (self.api.fmi3EnterInitializationMode)(
                self.c,
                tolerance.is_some() as u8,
                tolerance.unwrap_or(0.0),
                start,
                stop.is_some() as u8,
                stop.unwrap_or(0.0),
            )
        }
    }

    fn exit_initialization_mode(&self) -> i32 {
        // SAFETY: our instance.
        unsafe { (self.api.fmi3ExitInitializationMode)(self.c) }
    }

    fn do_step(&self, t: f64, h: f64, no_set_fmu_state_prior: bool, flags: bool) -> StepAnswer {
        let mut out = [0xAAu8; 3];
        let mut last = f64::NAN;
        let [event, terminate, early] = &mut out;
        let p = |b: &mut u8| -> *mut u8 { if flags { b } else { std::ptr::null_mut() } };
        // SAFETY: our instance; each pointer is null or one writable value.
        let status = unsafe {
            (self.api.fmi3DoStep)(
                self.c,
                t,
                h,
                no_set_fmu_state_prior as u8,
                p(event),
                p(terminate),
                p(early),
                &mut last,
            )
        };
        StepAnswer {
            status,
            flags: flags.then_some(out),
            last_successful_time: Some(last),
        }
    }

    fn terminate(&self) -> i32 {
        // SAFETY: our instance.
        unsafe { (self.api.fmi3Terminate)(self.c) }
    }

    fn reset(&self) -> i32 {
        // SAFETY: our instance.
        unsafe { (self.api.fmi3Reset)(self.c) }
    }

    unsafe fn set_debug_logging(&self, on: u8, n: usize, categories: *const *const c_char) -> i32 {
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi3SetDebugLogging)(self.c, on, n, categories) }
    }

    unsafe fn get_float64(
        &self,
        vrs: *const u32,
        nvr: usize,
        values: *mut f64,
        n_values: usize,
    ) -> i32 {
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi3GetFloat64)(self.c, vrs, nvr, values, n_values) }
    }

    unsafe fn set_float64(
        &self,
        vrs: *const u32,
        nvr: usize,
        values: *const f64,
        n_values: usize,
    ) -> i32 {
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi3SetFloat64)(self.c, vrs, nvr, values, n_values) }
    }

    unsafe fn get_int32(
        &self,
        vrs: *const u32,
        nvr: usize,
        values: *mut i32,
        n_values: usize,
    ) -> i32 {
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi3GetInt32)(self.c, vrs, nvr, values, n_values) }
    }

    unsafe fn set_int32(
        &self,
        vrs: *const u32,
        nvr: usize,
        values: *const i32,
        n_values: usize,
    ) -> i32 {
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi3SetInt32)(self.c, vrs, nvr, values, n_values) }
    }

    unsafe fn get_boolean(
        &self,
        vrs: *const u32,
        nvr: usize,
        values: *mut u8,
        n_values: usize,
    ) -> i32 {
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi3GetBoolean)(self.c, vrs, nvr, values, n_values) }
    }

    unsafe fn set_boolean(
        &self,
        vrs: *const u32,
        nvr: usize,
        values: *const u8,
        n_values: usize,
    ) -> i32 {
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi3SetBoolean)(self.c, vrs, nvr, values, n_values) }
    }

    unsafe fn get_string(
        &self,
        vrs: *const u32,
        nvr: usize,
        values: *mut *const c_char,
        n_values: usize,
    ) -> i32 {
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi3GetString)(self.c, vrs, nvr, values, n_values) }
    }

    unsafe fn set_string(
        &self,
        vrs: *const u32,
        nvr: usize,
        values: *const *const c_char,
        n_values: usize,
    ) -> i32 {
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi3SetString)(self.c, vrs, nvr, values, n_values) }
    }

    unsafe fn get_fmu_state(&self, state: *mut FmuState) -> i32 {
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi3GetFMUState)(self.c, state) }
    }

    unsafe fn set_fmu_state(&self, state: FmuState) -> i32 {
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi3SetFMUState)(self.c, state) }
    }

    unsafe fn free_fmu_state(&self, state: *mut FmuState) -> i32 {
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi3FreeFMUState)(self.c, state) }
    }

    unsafe fn serialized_fmu_state_size(&self, state: FmuState, size: *mut usize) -> i32 {
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi3SerializedFMUStateSize)(self.c, state, size) }
    }

    unsafe fn serialize_fmu_state(&self, state: FmuState, bytes: *mut u8, size: usize) -> i32 {
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi3SerializeFMUState)(self.c, state, bytes, size) }
    }

    unsafe fn deserialize_fmu_state(
        &self,
        bytes: *const u8,
        size: usize,
        state: *mut FmuState,
    ) -> i32 {
        // SAFETY: the caller's contract.
        unsafe { (self.api.fmi3DeserializeFMUState)(self.c, bytes, size, state) }
    }
}
