//! The 34 FMI 2.0 co-simulation functions and, in [`fmi3`], the 75 FMI 3.0 functions: the only
//! `unsafe` and the only exported symbols.
//!
//! Every entry point checks its pointers, bounds every length and count it is given before it
//! reads or allocates by it ([`crate::limits`]), runs the call under [`panic_hook::guarded`] (a panic
//! becomes `fmi2Error` with its message and location logged through the instance's logger, and
//! nothing reaches stderr), and reaches the instance through the registry of live instances
//! (`registry.rs`: an `fmi2Component` is a token, never dereferenced, so null, foreign and freed
//! ones are refused and `fmi2FreeInstance` is safe against a concurrent call) and a per-instance
//! mutex (`try_lock`: a second thread calling the same instance at the same time gets `fmi2Error`
//! and a logged reason instead of a data race). Messages go only to the FMI logger callback, with
//! `%` escaped as `%%` (the logger is printf-like). The process-wide state is the panic hook
//! ([`panic_hook`]) and the registry.

#![allow(non_snake_case)]

use crate::instance::{Instance, LogSink, Operation, Status};
use crate::state::Snapshot;
use crate::vars::{Type, Value};
use std::collections::HashMap;
use std::ffi::{CString, c_char, c_int, c_void};
use std::sync::Arc;

type Fmi2Status = c_int;
type Fmi2Boolean = c_int;
type Fmi2Component = *mut c_void;
type Fmi2State = *mut c_void;

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

struct Inner {
    inst: Instance,
    strings: Vec<CString>,
    snapshots: HashMap<usize, Box<Snapshot>>,
}

/// The FMI 3.0 logger callback type (`fmi3LogMessageCallback`: not variadic, no instance name).
pub type Logger3Fn = unsafe extern "C" fn(
    env: *mut c_void,
    status: c_int,
    category: *const c_char,
    message: *const c_char,
);

/// The master's logger: FMI 2.0 (printf-like) or FMI 3.0.
#[derive(Clone, Copy)]
enum LogFn {
    V2(LoggerFn),
    V3(Logger3Fn),
}

/// The logger callback with its environment.
struct CLogger {
    f: Option<LogFn>,
    env: *mut c_void,
    name: CString,
}

// SAFETY: the FMI standard lets the FMU call the logger, with the environment pointer, from any
// thread that is inside a call on the instance; the pointer is only passed back, never
// dereferenced here.
unsafe impl Send for CLogger {}
// SAFETY: as for Send: `log` only reads the fields and calls the master's callback. Two threads
// can log at once only when the master calls one instance from two threads (which FMI forbids
// and which the second thread is told about through this logger).
unsafe impl Sync for CLogger {}

fn c_text(s: &str) -> CString {
    CString::new(s.replace('\0', " ")).unwrap_or_default()
}

impl CLogger {
    fn log(&self, status: Status, category: &str, msg: &str) {
        self.emit(status, category, msg, true);
    }

    /// [`CLogger::log`] without the FMI 3.0 renaming (a message that names both interfaces).
    fn log_verbatim(&self, status: Status, category: &str, msg: &str) {
        self.emit(status, category, msg, false);
    }

    fn emit(&self, status: Status, category: &str, msg: &str, rename: bool) {
        let cat = c_text(category);
        match self.f {
            None => {}
            Some(LogFn::V2(f)) => {
                let text = c_text(&msg.replace('%', "%%"));
                // SAFETY: `f` is the master's logger; all strings are valid NUL-terminated C
                // strings that outlive the call, and the message contains no unescaped format
                // directives.
                unsafe {
                    f(
                        self.env,
                        self.name.as_ptr(),
                        status as c_int,
                        cat.as_ptr(),
                        text.as_ptr(),
                    )
                };
            }
            Some(LogFn::V3(f)) => {
                let text = c_text(&if rename {
                    fmi3::in_fmi3_terms(msg)
                } else {
                    msg.to_string()
                });
                // SAFETY: `f` is the master's fmi3LogMessageCallback; the strings are valid
                // NUL-terminated C strings that outlive the call (the message is not a format).
                unsafe { f(self.env, status as c_int, cat.as_ptr(), text.as_ptr()) };
            }
        }
    }
}

/// Borrow a C array of `n` elements; null is allowed only for length 0, and `n` must be at most
/// `max` (checked before the array is touched).
///
/// # Safety
/// `p` must point to `n` valid elements when non-null.
unsafe fn slice<'a, T>(p: *const T, n: usize, max: usize) -> Option<&'a [T]> {
    if n == 0 {
        return Some(&[]);
    }
    if p.is_null() || n > max || n > isize::MAX as usize / std::mem::size_of::<T>().max(1) {
        return None;
    }
    // SAFETY: guaranteed by the caller (the master passes arrays of `n` elements).
    Some(unsafe { std::slice::from_raw_parts(p, n) })
}

/// # Safety
/// As [`slice`], for writing.
unsafe fn slice_mut<'a, T>(p: *mut T, n: usize, max: usize) -> Option<&'a mut [T]> {
    if n == 0 {
        return Some(&mut []);
    }
    if p.is_null() || n > max || n > isize::MAX as usize / std::mem::size_of::<T>().max(1) {
        return None;
    }
    // SAFETY: guaranteed by the caller.
    Some(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

/// Why a C string argument is refused.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum TextError {
    Null,
    TooLong(usize),
    NotUtf8,
}

impl TextError {
    fn describe(self, what: &str) -> String {
        match self {
            TextError::Null => format!("{what} is a null pointer"),
            TextError::TooLong(max) => format!("{what} is longer than {max} bytes"),
            TextError::NotUtf8 => format!("{what} is not UTF-8"),
        }
    }
}

/// A NUL-terminated string of at most `max` bytes, read without looking past its terminator or
/// past `max + 1` bytes.
///
/// # Safety
/// `p` is null or a NUL-terminated string.
unsafe fn text<'a>(p: *const c_char, max: usize) -> Result<&'a str, TextError> {
    if p.is_null() {
        return Err(TextError::Null);
    }
    let mut n = 0usize;
    loop {
        // SAFETY: the string is NUL-terminated and no byte after the terminator is read.
        if unsafe { *p.add(n) } == 0 {
            break;
        }
        if n == max {
            return Err(TextError::TooLong(max));
        }
        n += 1;
    }
    // SAFETY: the `n` bytes before the terminator were just read.
    let bytes = unsafe { std::slice::from_raw_parts(p as *const u8, n) };
    std::str::from_utf8(bytes).map_err(|_| TextError::NotUtf8)
}

fn null_arg(inner: &Inner, func: Operation, what: &str) -> Status {
    inner.inst.error(&format!(
        "{func}: {what} is a null pointer, or its length is over the limit ({} elements)",
        crate::limits::MAX_VALUE_REFS
    ))
}

mod binding;
mod common;
mod cosim;
pub mod fmi3;
mod fmu_state;
pub mod panic_hook;
mod registry;
mod values;

pub use registry::live_instances;
use registry::status;

pub use common::*;
pub use cosim::*;
pub use fmi3::*;
pub use fmu_state::*;
pub use values::*;
