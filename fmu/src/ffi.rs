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

// ---------------------------------------------------------------------------------------------
// Common functions

/// `fmi2GetTypesPlatform`.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetTypesPlatform() -> *const c_char {
    c"default".as_ptr()
}

/// `fmi2GetVersion`.
#[unsafe(no_mangle)]
pub extern "C" fn fmi2GetVersion() -> *const c_char {
    c"2.0".as_ptr()
}

/// `fmi2SetDebugLogging`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetDebugLogging(
    c: Fmi2Component,
    logging_on: Fmi2Boolean,
    n: usize,
    categories: *const *const c_char,
) -> Fmi2Status {
    status(c, "fmi2SetDebugLogging", |inner| {
        // SAFETY: the master passes `n` category strings.
        let Some(cats) = (unsafe { slice(categories, n) }) else {
            return null_arg(inner, "fmi2SetDebugLogging", "categories");
        };
        let mut names = Vec::with_capacity(n);
        for p in cats {
            // SAFETY: each entry is a C string (checked for null).
            match unsafe { text(*p) } {
                Some(s) => names.push(s.to_string()),
                None => return null_arg(inner, "fmi2SetDebugLogging", "a category"),
            }
        }
        inner.inst.set_debug_logging(logging_on != 0, &names)
    })
}

/// `fmi2Instantiate`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Instantiate(
    instance_name: *const c_char,
    fmu_type: c_int,
    guid: *const c_char,
    resource_location: *const c_char,
    functions: *const CallbackFunctions,
    _visible: Fmi2Boolean,
    logging_on: Fmi2Boolean,
) -> Fmi2Component {
    let r = catch_unwind(AssertUnwindSafe(|| {
        if functions.is_null() {
            return std::ptr::null_mut();
        }
        // SAFETY: non-null and, per FMI 2.0, a valid fmi2CallbackFunctions.
        let fns = unsafe { &*functions };
        // SAFETY: null or C strings.
        let name = unsafe { text(instance_name) };
        let logger = CLogger {
            f: fns.logger,
            env: fns.component_environment,
            name: c_text(name.unwrap_or("")),
        };
        let sink: LogSink = Box::new(move |s, cat, msg| logger.log(s, cat, msg));
        let fail = |sink: LogSink, msg: &str| {
            sink(Status::Error, "logStatusError", msg);
            std::ptr::null_mut()
        };
        let Some(name) = name else {
            return fail(
                sink,
                "fmi2Instantiate: instanceName is a null pointer or not UTF-8",
            );
        };
        if fmu_type != 1 {
            return fail(
                sink,
                &format!(
                    "fmi2Instantiate: fmuType {fmu_type} requested; this FMU supports only co-simulation (fmi2CoSimulation = 1), not model exchange"
                ),
            );
        }
        // SAFETY: null or C strings.
        let Some(guid) = (unsafe { text(guid) }) else {
            return fail(sink, "fmi2Instantiate: fmuGUID is a null pointer");
        };
        // SAFETY: null or C strings.
        let res = unsafe { text(resource_location) };
        match Instance::new(name, guid, res, logging_on != 0, sink) {
            Ok(inst) => Box::into_raw(Box::new(Handle {
                magic: MAGIC,
                inner: Mutex::new(Inner {
                    inst,
                    strings: Vec::new(),
                    snapshots: HashMap::new(),
                }),
            })) as Fmi2Component,
            Err((sink, msg)) => fail(sink, &msg),
        }
    }));
    r.unwrap_or(std::ptr::null_mut())
}

/// `fmi2FreeInstance`: safe with NULL and after any error.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeInstance(c: Fmi2Component) {
    let _ = catch_unwind(AssertUnwindSafe(|| {
        if c.is_null() {
            return;
        }
        let h = c as *mut Handle;
        // SAFETY: a pointer from fmi2Instantiate (see `with_inst`).
        let handle = unsafe { &mut *h };
        if handle.magic != MAGIC {
            return;
        }
        if handle
            .inner
            .try_lock()
            .is_err_and(|e| matches!(e, TryLockError::WouldBlock))
        {
            return; // in use by another thread: leaking beats a use-after-free
        }
        handle.magic = FREED;
        // SAFETY: created by Box::into_raw in fmi2Instantiate, freed once (magic now cleared).
        drop(unsafe { Box::from_raw(h) });
    }));
}

/// `fmi2SetupExperiment`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetupExperiment(
    c: Fmi2Component,
    _tolerance_defined: Fmi2Boolean,
    _tolerance: f64,
    start_time: f64,
    stop_time_defined: Fmi2Boolean,
    stop_time: f64,
) -> Fmi2Status {
    status(c, "fmi2SetupExperiment", |i| {
        i.inst
            .setup_experiment(start_time, (stop_time_defined != 0).then_some(stop_time))
    })
}

/// `fmi2EnterInitializationMode`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2EnterInitializationMode(c: Fmi2Component) -> Fmi2Status {
    status(c, "fmi2EnterInitializationMode", |i| {
        i.inst.enter_initialization_mode()
    })
}

/// `fmi2ExitInitializationMode`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: Fmi2Component) -> Fmi2Status {
    status(c, "fmi2ExitInitializationMode", |i| {
        i.inst.exit_initialization_mode()
    })
}

/// `fmi2Terminate`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Terminate(c: Fmi2Component) -> Fmi2Status {
    status(c, "fmi2Terminate", |i| i.inst.terminate())
}

/// `fmi2Reset`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Reset(c: Fmi2Component) -> Fmi2Status {
    status(c, "fmi2Reset", |i| i.inst.reset())
}

// ---------------------------------------------------------------------------------------------
// Get / set

fn get_values<T>(
    inner: &mut Inner,
    func: &str,
    ty: Type,
    vr: *const u32,
    nvr: usize,
    out: *mut T,
    mut conv: impl FnMut(Value, &mut Vec<CString>) -> T,
) -> Status {
    // SAFETY: the master passes `nvr` references and room for `nvr` values.
    let (Some(vrs), Some(out)) = (unsafe { slice(vr, nvr) }, unsafe { slice_mut(out, nvr) }) else {
        return null_arg(inner, func, "vr or value");
    };
    match inner.inst.get(func, ty, vrs) {
        Ok(values) => {
            inner.strings.clear();
            for (o, v) in out.iter_mut().zip(values) {
                *o = conv(v, &mut inner.strings);
            }
            Status::Ok
        }
        Err(s) => s,
    }
}

/// `fmi2GetReal`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetReal(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    value: *mut f64,
) -> Fmi2Status {
    status(c, "fmi2GetReal", |i| {
        get_values(
            i,
            "fmi2GetReal",
            Type::Real,
            vr,
            nvr,
            value,
            |v, _| match v {
                Value::Real(x) => x,
                _ => f64::NAN,
            },
        )
    })
}

/// `fmi2GetInteger`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetInteger(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    value: *mut c_int,
) -> Fmi2Status {
    status(c, "fmi2GetInteger", |i| {
        get_values(
            i,
            "fmi2GetInteger",
            Type::Integer,
            vr,
            nvr,
            value,
            |v, _| match v {
                Value::Integer(x) => x,
                _ => 0,
            },
        )
    })
}

/// `fmi2GetBoolean`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetBoolean(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    value: *mut Fmi2Boolean,
) -> Fmi2Status {
    status(c, "fmi2GetBoolean", |i| {
        get_values(
            i,
            "fmi2GetBoolean",
            Type::Boolean,
            vr,
            nvr,
            value,
            |v, _| matches!(v, Value::Boolean(true)) as Fmi2Boolean,
        )
    })
}

/// `fmi2GetString`: the returned strings stay valid until the next fmi2GetString call on the
/// same instance (or its freeing).
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetString(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    value: *mut *const c_char,
) -> Fmi2Status {
    status(c, "fmi2GetString", |i| {
        get_values(
            i,
            "fmi2GetString",
            Type::String,
            vr,
            nvr,
            value,
            |v, store| {
                let s = match v {
                    Value::String(s) => c_text(&s),
                    _ => CString::default(),
                };
                let p = s.as_ptr();
                store.push(s);
                p
            },
        )
    })
}

fn set_values<T: Copy>(
    inner: &mut Inner,
    func: &str,
    vr: *const u32,
    nvr: usize,
    value: *const T,
    mut conv: impl FnMut(T) -> Option<Value>,
) -> Status {
    // SAFETY: the master passes `nvr` references and values.
    let (Some(vrs), Some(vals)) = (unsafe { slice(vr, nvr) }, unsafe { slice(value, nvr) }) else {
        return null_arg(inner, func, "vr or value");
    };
    let mut values = Vec::with_capacity(nvr);
    for v in vals {
        match conv(*v) {
            Some(v) => values.push(v),
            None => return null_arg(inner, func, "a string value"),
        }
    }
    inner.inst.set(func, vrs, values)
}

/// `fmi2SetReal`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetReal(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    value: *const f64,
) -> Fmi2Status {
    status(c, "fmi2SetReal", |i| {
        set_values(i, "fmi2SetReal", vr, nvr, value, |x| Some(Value::Real(x)))
    })
}

/// `fmi2SetInteger`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetInteger(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    value: *const c_int,
) -> Fmi2Status {
    status(c, "fmi2SetInteger", |i| {
        set_values(i, "fmi2SetInteger", vr, nvr, value, |x| {
            Some(Value::Integer(x))
        })
    })
}

/// `fmi2SetBoolean`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetBoolean(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    value: *const Fmi2Boolean,
) -> Fmi2Status {
    status(c, "fmi2SetBoolean", |i| {
        set_values(i, "fmi2SetBoolean", vr, nvr, value, |x| {
            Some(Value::Boolean(x != 0))
        })
    })
}

/// `fmi2SetString`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetString(
    c: Fmi2Component,
    vr: *const u32,
    nvr: usize,
    value: *const *const c_char,
) -> Fmi2Status {
    status(c, "fmi2SetString", |i| {
        set_values(i, "fmi2SetString", vr, nvr, value, |p| {
            // SAFETY: each value is null (rejected) or a C string.
            unsafe { text(p) }.map(|s| Value::String(s.to_string()))
        })
    })
}

// ---------------------------------------------------------------------------------------------
// FMU state

/// A snapshot pointer owned by this instance (null, foreign and freed pointers are rejected).
fn known(inner: &Inner, p: Fmi2State) -> bool {
    !p.is_null() && inner.snapshots.contains_key(&(p as usize))
}

fn store_snapshot(inner: &mut Inner, slot: &mut Fmi2State, snap: Snapshot) {
    if known(inner, *slot) {
        if let Some(b) = inner.snapshots.get_mut(&(*slot as usize)) {
            **b = snap;
        }
    } else {
        let mut b = Box::new(snap);
        let p = &mut *b as *mut Snapshot as Fmi2State;
        inner.snapshots.insert(p as usize, b);
        *slot = p;
    }
}

/// `fmi2GetFMUstate`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetFMUstate(c: Fmi2Component, state: *mut Fmi2State) -> Fmi2Status {
    status(c, "fmi2GetFMUstate", |i| {
        if state.is_null() {
            return null_arg(i, "fmi2GetFMUstate", "FMUstate");
        }
        // SAFETY: non-null pointer to the master's fmi2FMUstate variable.
        let slot = unsafe { &mut *state };
        if !slot.is_null() && !known(i, *slot) {
            return i
                .inst
                .error("fmi2GetFMUstate: *FMUstate is neither NULL nor a state of this instance");
        }
        match i.inst.get_state() {
            Ok(snap) => {
                store_snapshot(i, slot, snap);
                Status::Ok
            }
            Err(s) => s,
        }
    })
}

/// `fmi2SetFMUstate`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetFMUstate(c: Fmi2Component, state: Fmi2State) -> Fmi2Status {
    status(c, "fmi2SetFMUstate", |i| {
        if !known(i, state) {
            return i
                .inst
                .error("fmi2SetFMUstate: FMUstate is not a state of this instance (null, freed or foreign)");
        }
        let snap = (*i.snapshots[&(state as usize)]).clone();
        i.inst.set_state(&snap)
    })
}

/// `fmi2FreeFMUstate`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeFMUstate(c: Fmi2Component, state: *mut Fmi2State) -> Fmi2Status {
    status(c, "fmi2FreeFMUstate", |i| {
        if let Err(s) = i.inst.check_state_call("fmi2FreeFMUstate") {
            return s;
        }
        if state.is_null() {
            return null_arg(i, "fmi2FreeFMUstate", "FMUstate");
        }
        // SAFETY: non-null pointer to the master's fmi2FMUstate variable.
        let slot = unsafe { &mut *state };
        if slot.is_null() {
            return Status::Ok;
        }
        if i.snapshots.remove(&(*slot as usize)).is_none() {
            return i
                .inst
                .error("fmi2FreeFMUstate: FMUstate is not a state of this instance");
        }
        *slot = std::ptr::null_mut();
        Status::Ok
    })
}

/// `fmi2SerializedFMUstateSize`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializedFMUstateSize(
    c: Fmi2Component,
    state: Fmi2State,
    size: *mut usize,
) -> Fmi2Status {
    status(c, "fmi2SerializedFMUstateSize", |i| {
        if let Err(s) = i.inst.check_state_call("fmi2SerializedFMUstateSize") {
            return s;
        }
        if size.is_null() {
            return null_arg(i, "fmi2SerializedFMUstateSize", "size");
        }
        if !known(i, state) {
            return i
                .inst
                .error("fmi2SerializedFMUstateSize: FMUstate is not a state of this instance");
        }
        let n = i.snapshots[&(state as usize)].to_bytes().len();
        // SAFETY: non-null pointer to the master's size_t.
        unsafe { *size = n };
        Status::Ok
    })
}

/// `fmi2SerializeFMUstate`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SerializeFMUstate(
    c: Fmi2Component,
    state: Fmi2State,
    bytes: *mut u8,
    size: usize,
) -> Fmi2Status {
    status(c, "fmi2SerializeFMUstate", |i| {
        if let Err(s) = i.inst.check_state_call("fmi2SerializeFMUstate") {
            return s;
        }
        if !known(i, state) {
            return i
                .inst
                .error("fmi2SerializeFMUstate: FMUstate is not a state of this instance");
        }
        let data = i.snapshots[&(state as usize)].to_bytes();
        if size < data.len() {
            return i.inst.error(&format!(
                "fmi2SerializeFMUstate: buffer of {size} bytes is smaller than the state ({} bytes; ask fmi2SerializedFMUstateSize)",
                data.len()
            ));
        }
        // SAFETY: the master provides `size` writable bytes.
        let Some(out) = (unsafe { slice_mut(bytes, size) }) else {
            return null_arg(i, "fmi2SerializeFMUstate", "serializedState");
        };
        out[..data.len()].copy_from_slice(&data);
        Status::Ok
    })
}

/// `fmi2DeSerializeFMUstate`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DeSerializeFMUstate(
    c: Fmi2Component,
    bytes: *const u8,
    size: usize,
    state: *mut Fmi2State,
) -> Fmi2Status {
    status(c, "fmi2DeSerializeFMUstate", |i| {
        if let Err(s) = i.inst.check_state_call("fmi2DeSerializeFMUstate") {
            return s;
        }
        // SAFETY: the master passes `size` readable bytes.
        let Some(data) = (unsafe { slice(bytes, size) }) else {
            return null_arg(i, "fmi2DeSerializeFMUstate", "serializedState");
        };
        if state.is_null() {
            return null_arg(i, "fmi2DeSerializeFMUstate", "FMUstate");
        }
        // SAFETY: non-null pointer to the master's fmi2FMUstate variable.
        let slot = unsafe { &mut *state };
        if !slot.is_null() && !known(i, *slot) {
            return i.inst.error(
                "fmi2DeSerializeFMUstate: *FMUstate is neither NULL nor a state of this instance",
            );
        }
        let snap = match Snapshot::from_bytes(data) {
            Ok(s) => s,
            Err(e) => return i.inst.error(&format!("fmi2DeSerializeFMUstate: {e}")),
        };
        if let Err(s) = i.inst.check_snapshot("fmi2DeSerializeFMUstate", &snap) {
            return s;
        }
        store_snapshot(i, slot, snap);
        Status::Ok
    })
}

// ---------------------------------------------------------------------------------------------
// Unsupported capabilities

use crate::state::Phase::*;

/// `fmi2GetDirectionalDerivative`: not supported (providesDirectionalDerivative = false).
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetDirectionalDerivative(
    c: Fmi2Component,
    _unknown: *const u32,
    _n_unknown: usize,
    _known: *const u32,
    _n_known: usize,
    _dv_known: *const f64,
    _dv_unknown: *mut f64,
) -> Fmi2Status {
    status(c, "fmi2GetDirectionalDerivative", |i| {
        i.inst.unsupported(
            "fmi2GetDirectionalDerivative",
            &[InitializationMode, StepComplete, Terminated, Error],
            "directional derivatives (providesDirectionalDerivative = false)",
        )
    })
}

/// `fmi2SetRealInputDerivatives`: not supported (canInterpolateInputs = false).
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2SetRealInputDerivatives(
    c: Fmi2Component,
    _vr: *const u32,
    _nvr: usize,
    _order: *const c_int,
    _value: *const f64,
) -> Fmi2Status {
    status(c, "fmi2SetRealInputDerivatives", |i| {
        i.inst.unsupported(
            "fmi2SetRealInputDerivatives",
            &[Instantiated, InitializationMode, StepComplete],
            "input derivatives (canInterpolateInputs = false)",
        )
    })
}

/// `fmi2GetRealOutputDerivatives`: not supported (maxOutputDerivativeOrder = 0).
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetRealOutputDerivatives(
    c: Fmi2Component,
    _vr: *const u32,
    _nvr: usize,
    _order: *const c_int,
    _value: *mut f64,
) -> Fmi2Status {
    status(c, "fmi2GetRealOutputDerivatives", |i| {
        i.inst.unsupported(
            "fmi2GetRealOutputDerivatives",
            &[StepComplete, Terminated, Error],
            "output derivatives (maxOutputDerivativeOrder = 0)",
        )
    })
}

// ---------------------------------------------------------------------------------------------
// Co-simulation

/// `fmi2DoStep` (synchronous).
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2DoStep(
    c: Fmi2Component,
    current_communication_point: f64,
    communication_step_size: f64,
    _no_set_fmu_state_prior: Fmi2Boolean,
) -> Fmi2Status {
    status(c, "fmi2DoStep", |i| {
        i.inst
            .do_step(current_communication_point, communication_step_size)
    })
}

/// `fmi2CancelStep`: steps are synchronous, so there is never a step to cancel.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2CancelStep(c: Fmi2Component) -> Fmi2Status {
    status(c, "fmi2CancelStep", |i| {
        i.inst.error(
            "fmi2CancelStep: Illegal call sequence (no asynchronous step is in progress; canRunAsynchronuously = false)",
        )
    })
}

fn status_query<T>(
    inner: &mut Inner,
    func: &str,
    kind: c_int,
    out: *mut T,
    answer: impl FnOnce(&Instance, c_int) -> Option<T>,
) -> Status {
    if let Err(s) = inner.inst.check_status_query(func) {
        return s;
    }
    if out.is_null() {
        return null_arg(inner, func, "value");
    }
    match answer(&inner.inst, kind) {
        Some(v) => {
            // SAFETY: non-null pointer to the master's variable.
            unsafe { *out = v };
            Status::Ok
        }
        None => {
            inner.inst.warn(&format!(
                "{func}: status kind {kind} is not available (fmi2Discard)"
            ));
            Status::Discard
        }
    }
}

/// `fmi2GetStatus`: only meaningful for asynchronous steps; answers fmi2Discard.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStatus(
    c: Fmi2Component,
    kind: c_int,
    value: *mut Fmi2Status,
) -> Fmi2Status {
    status(c, "fmi2GetStatus", |i| {
        status_query(i, "fmi2GetStatus", kind, value, |_, _| None)
    })
}

/// `fmi2GetRealStatus`: fmi2LastSuccessfulTime.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetRealStatus(
    c: Fmi2Component,
    kind: c_int,
    value: *mut f64,
) -> Fmi2Status {
    status(c, "fmi2GetRealStatus", |i| {
        status_query(i, "fmi2GetRealStatus", kind, value, |inst, k| {
            (k == 2).then(|| inst.last_successful_time())
        })
    })
}

/// `fmi2GetIntegerStatus`: no integer status kinds exist in FMI 2.0 (fmi2Discard).
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetIntegerStatus(
    c: Fmi2Component,
    kind: c_int,
    value: *mut c_int,
) -> Fmi2Status {
    status(c, "fmi2GetIntegerStatus", |i| {
        status_query(i, "fmi2GetIntegerStatus", kind, value, |_, _| None)
    })
}

/// `fmi2GetBooleanStatus`: fmi2Terminated (always false: the FMU never asks to stop).
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetBooleanStatus(
    c: Fmi2Component,
    kind: c_int,
    value: *mut Fmi2Boolean,
) -> Fmi2Status {
    status(c, "fmi2GetBooleanStatus", |i| {
        status_query(i, "fmi2GetBooleanStatus", kind, value, |_, k| {
            (k == 3).then_some(0)
        })
    })
}

/// `fmi2GetStringStatus`: fmi2PendingStatus is never available (fmi2Discard).
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2GetStringStatus(
    c: Fmi2Component,
    kind: c_int,
    value: *mut *const c_char,
) -> Fmi2Status {
    status(c, "fmi2GetStringStatus", |i| {
        status_query(i, "fmi2GetStringStatus", kind, value, |_, _| None)
    })
}
