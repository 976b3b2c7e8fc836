//! The C types of the interface: the FMI 2.0 status, Boolean, instance and state handles, and
//! the master's callbacks (the FMI 2.0 callback functions, the FMI 3.0 log callback).

use std::ffi::{c_char, c_int, c_void};

pub(super) type Fmi2Status = c_int;
pub(super) type Fmi2Boolean = c_int;
pub(super) type Fmi2Component = *mut c_void;
pub(super) type Fmi2State = *mut c_void;

/// The FMI logger callback type (printf-like, variadic).
pub type LoggerFn = unsafe extern "C" fn(
    env: *mut c_void,
    instance: *const c_char,
    status: c_int,
    category: *const c_char,
    message: *const c_char,
    ...
);

/// `fmi2CallbackFunctions`. The FMU never allocates through the master (Rust's allocator is used;
/// `canNotUseMemoryManagementFunctions = true`), so only the logger and its environment are used.
#[repr(C)]
pub struct CallbackFunctions {
    /// Logger (may be NULL: then nothing is logged).
    pub logger: Option<LoggerFn>,
    /// Unused.
    pub allocate_memory: Option<unsafe extern "C" fn(usize, usize) -> *mut c_void>,
    /// Unused.
    pub free_memory: Option<unsafe extern "C" fn(*mut c_void)>,
    /// Unused (no asynchronous steps).
    pub step_finished: Option<unsafe extern "C" fn(*mut c_void, c_int)>,
    /// Passed back to the logger.
    pub component_environment: *mut c_void,
}

/// The FMI 3.0 logger callback type (`fmi3LogMessageCallback`: not variadic, no instance name).
pub type Logger3Fn = unsafe extern "C" fn(
    env: *mut c_void,
    status: c_int,
    category: *const c_char,
    message: *const c_char,
);
