//! The 34 FMI 2.0 co-simulation functions: the only `unsafe` and the only exported symbols.
//!
//! Every entry point checks its pointers and lengths, catches panics (`catch_unwind`) and turns
//! them into `fmi2Error` with a logged message, and reaches the instance through a per-instance
//! mutex (`try_lock`: a second thread calling the same instance at the same time gets an error
//! instead of a data race). There is no global state; messages go only to the FMI logger callback,
//! with `%` escaped as `%%` (the logger is printf-like).

#![allow(non_snake_case)]

use crate::instance::{Instance, LogSink, Status};
use crate::state::Snapshot;
use crate::vars::{Type, Value};
use std::collections::HashMap;
use std::ffi::{CStr, CString, c_char, c_int, c_void};
use std::panic::{AssertUnwindSafe, catch_unwind};
use std::sync::{Mutex, TryLockError};

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

const MAGIC: u64 = 0x454E_4156_464D_5531; // "ENAVFMU1"
const FREED: u64 = 0xDEAD_DEAD_DEAD_DEAD;

struct Inner {
    inst: Instance,
    strings: Vec<CString>,
    snapshots: HashMap<usize, Box<Snapshot>>,
}

struct Handle {
    magic: u64,
    inner: Mutex<Inner>,
}

/// The logger callback with its environment; the master guarantees it may be called from the
/// thread that calls the instance.
struct CLogger {
    f: Option<LoggerFn>,
    env: *mut c_void,
    name: CString,
}

// SAFETY: the FMI standard lets the FMU call the logger with the environment pointer from any
// thread that calls into the instance; the pointer is only passed back, never dereferenced here.
unsafe impl Send for CLogger {}

fn c_text(s: &str) -> CString {
    CString::new(s.replace('\0', " ")).unwrap_or_default()
}

impl CLogger {
    fn log(&self, status: Status, category: &str, msg: &str) {
        if let Some(f) = self.f {
            let cat = c_text(category);
            let text = c_text(&msg.replace('%', "%%"));
            // SAFETY: `f` is the master's logger; all strings are valid NUL-terminated C strings
            // that outlive the call, and the message contains no unescaped format directives.
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
    }
}

fn panic_text(e: &(dyn std::any::Any + Send)) -> String {
    e.downcast_ref::<&str>()
        .map(|s| s.to_string())
        .or_else(|| e.downcast_ref::<String>().cloned())
        .unwrap_or_else(|| "unknown panic".into())
}

/// Run `f` on the instance behind `c`; null, freed or foreign pointers, concurrent calls and
/// panics give `fmi2Error`.
fn with_inst<T>(c: Fmi2Component, func: &str, fail: T, f: impl FnOnce(&mut Inner) -> T) -> T {
    if c.is_null() {
        return fail;
    }
    let handle = c as *const Handle;
    // SAFETY: a non-null component must be a pointer returned by fmi2Instantiate and not yet
    // freed (FMI 2.0); the magic check rejects freed handles while their memory is still mapped.
    let handle = unsafe { &*handle };
    if handle.magic != MAGIC {
        return fail;
    }
    let mut guard = match handle.inner.try_lock() {
        Ok(g) => g,
        Err(TryLockError::Poisoned(p)) => p.into_inner(),
        Err(TryLockError::WouldBlock) => return fail,
    };
    match catch_unwind(AssertUnwindSafe(|| f(&mut guard))) {
        Ok(v) => v,
        Err(e) => {
            let msg = format!("{func}: internal error (caught panic: {})", panic_text(&*e));
            let _ = catch_unwind(AssertUnwindSafe(|| guard.inst.poison(&msg)));
            fail
        }
    }
}

fn status(c: Fmi2Component, func: &str, f: impl FnOnce(&mut Inner) -> Status) -> Fmi2Status {
    with_inst(c, func, Status::Error, f) as Fmi2Status
}

/// Borrow a C array; null is allowed only for length 0.
///
/// # Safety
/// `p` must point to `n` valid elements when non-null.
unsafe fn slice<'a, T>(p: *const T, n: usize) -> Option<&'a [T]> {
    if n == 0 {
        return Some(&[]);
    }
    if p.is_null() || n > isize::MAX as usize / std::mem::size_of::<T>().max(1) {
        return None;
    }
    // SAFETY: guaranteed by the caller (the master passes arrays of `n` elements).
    Some(unsafe { std::slice::from_raw_parts(p, n) })
}

/// # Safety
/// As [`slice`], for writing.
unsafe fn slice_mut<'a, T>(p: *mut T, n: usize) -> Option<&'a mut [T]> {
    if n == 0 {
        return Some(&mut []);
    }
    if p.is_null() || n > isize::MAX as usize / std::mem::size_of::<T>().max(1) {
        return None;
    }
    // SAFETY: guaranteed by the caller.
    Some(unsafe { std::slice::from_raw_parts_mut(p, n) })
}

/// # Safety
/// `p` is null or a NUL-terminated string.
unsafe fn text<'a>(p: *const c_char) -> Option<&'a str> {
    if p.is_null() {
        return None;
    }
    // SAFETY: guaranteed by the caller.
    unsafe { CStr::from_ptr(p) }.to_str().ok()
}

fn null_arg(inner: &Inner, func: &str, what: &str) -> Status {
    inner.inst.error(&format!(
        "{func}: {what} is a null pointer (or an impossible length)"
    ))
}

mod common;
mod cosim;
mod fmu_state;
mod values;

pub use common::*;
pub use cosim::*;
pub use fmu_state::*;
pub use values::*;
