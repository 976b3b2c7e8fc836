//! The 34 FMI 2.0 co-simulation functions: the only `unsafe` and the only exported symbols.
//!
//! Every entry point checks its pointers, bounds every length and count it is given before it
//! reads or allocates by it ([`crate::limits`]), runs the call under [`panic_hook::guarded`] (a panic
//! becomes `fmi2Error` with its message and location logged through the instance's logger, and
//! nothing reaches stderr), and reaches the instance through a per-instance mutex (`try_lock`: a
//! second thread calling the same instance at the same time gets `fmi2Error` and a logged reason
//! instead of a data race). Messages go only to the FMI logger callback, with `%` escaped as `%%`
//! (the logger is printf-like). The only process-wide state is the panic hook ([`panic_hook`]).

#![allow(non_snake_case)]

use crate::instance::{Instance, LogSink, Status};
use crate::state::Snapshot;
use crate::vars::{Type, Value};
use std::collections::HashMap;
use std::ffi::{CString, c_char, c_int, c_void};
use std::sync::{Arc, Mutex, TryLockError};

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
    /// The master's logger, outside the lock so a refused concurrent call can still log.
    log: Arc<CLogger>,
    inner: Mutex<Inner>,
}

/// The logger callback with its environment.
struct CLogger {
    f: Option<LoggerFn>,
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

/// Run `f` on the instance behind `c`; null, freed or foreign pointers, concurrent calls and
/// panics give `fail`.
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
        Err(TryLockError::WouldBlock) => {
            let log = &handle.log;
            let _ = panic_hook::guarded(|| {
                log.log(
                    Status::Error,
                    "logStatusError",
                    &format!(
                        "{func}: the instance is busy: another thread is inside a call on it (FMI 2.0 allows one call at a time per instance); nothing was done"
                    ),
                )
            });
            return fail;
        }
    };
    match panic_hook::guarded(|| f(&mut guard)) {
        Ok(v) => v,
        Err(msg) => {
            let msg = format!("{func}: internal error (caught panic: {msg})");
            let _ = panic_hook::guarded(|| guard.inst.poison(&msg));
            fail
        }
    }
}

fn status(c: Fmi2Component, func: &str, f: impl FnOnce(&mut Inner) -> Status) -> Fmi2Status {
    with_inst(c, func, Status::Error, f) as Fmi2Status
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

fn null_arg(inner: &Inner, func: &str, what: &str) -> Status {
    inner.inst.error(&format!(
        "{func}: {what} is a null pointer, or its length is over the limit ({} elements)",
        crate::limits::MAX_VALUE_REFS
    ))
}

mod binding;
mod common;
mod cosim;
mod fmu_state;
pub mod panic_hook;
mod values;

pub use common::*;
pub use cosim::*;
pub use fmu_state::*;
pub use values::*;
