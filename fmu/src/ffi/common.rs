//! The fmi2 functions common to every FMI 2.0 interface: version, logging, instantiation,
//! experiment set-up, initialisation, termination and reset.

use super::args::{TextError, slice, text};
use super::inner::Inner;
use super::logger::{CLogger, LogFn, c_text};
use super::registry::status;
use super::types::{CallbackFunctions, Fmi2Boolean, Fmi2Component, Fmi2Status};
use super::{binding, panic_hook, registry};
use crate::instance::resolve_spec;
use crate::instance::{Instance, LogSink, Operation, Status};
use crate::limits::{MAX_CATEGORIES, MAX_GUID_BYTES, MAX_LOCATION_BYTES, MAX_STRING_BYTES};
use std::collections::HashMap;
use std::ffi::{c_char, c_int};
use std::sync::Arc;

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
    // SAFETY: the same contract.
    unsafe { set_debug_logging("fmi2SetDebugLogging", c, logging_on != 0, n, categories) }
}

/// The body of `fmi2SetDebugLogging` (and of `fmi3SetDebugLogging`) on behalf of `name`.
///
/// # Safety
/// FMI 2.0 / 3.0 calling conventions.
pub(super) unsafe fn set_debug_logging(
    name: &'static str,
    c: Fmi2Component,
    logging_on: bool,
    n: usize,
    categories: *const *const c_char,
) -> Fmi2Status {
    const F: Operation = Operation::SetDebugLogging;
    status(c, name, |inner| {
        // SAFETY: the master passes `n` category strings (n is bounded first).
        let Some(cats) = (unsafe { slice(categories, n, MAX_CATEGORIES) }) else {
            return inner.inst.error(&format!(
                "{F}: categories is a null pointer, or nCategories = {n} is over the limit of {MAX_CATEGORIES}"
            ));
        };
        let mut names = Vec::with_capacity(cats.len());
        for p in cats {
            // SAFETY: each entry is null (refused) or a C string.
            match unsafe { text(*p, MAX_STRING_BYTES) } {
                Ok(s) => names.push(s.to_string()),
                Err(e) => {
                    return inner
                        .inst
                        .error(&format!("{F}: {}", e.describe("a category")));
                }
            }
        }
        inner.inst.set_debug_logging(logging_on, &names)
    })
}

/// `fmi2Instantiate`: the library's binding decides which models it serves (see
/// [`crate::binding`]).
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
    let r = panic_hook::guarded(|| {
        if functions.is_null() {
            return std::ptr::null_mut();
        }
        // SAFETY: non-null and, per FMI 2.0, a valid fmi2CallbackFunctions.
        let fns = unsafe { &*functions };
        // SAFETY: null or C strings.
        let name = unsafe { text(instance_name, MAX_STRING_BYTES) };
        let logger = Arc::new(CLogger {
            f: fns.logger.map(LogFn::V2),
            env: fns.component_environment,
            name: c_text(name.unwrap_or("")),
        });
        let fail = |msg: &str| {
            logger.log(Status::Error, "logStatusError", msg);
            std::ptr::null_mut()
        };
        let name = match name {
            Ok(n) => n,
            Err(e) => return fail(&format!("fmi2Instantiate: {}", e.describe("instanceName"))),
        };
        if fmu_type != 1 {
            return fail(&format!(
                "fmi2Instantiate: fmuType {fmu_type} requested; this FMU supports only co-simulation (fmi2CoSimulation = 1), not model exchange"
            ));
        }
        // SAFETY: null or C strings.
        let guid = match unsafe { text(guid, MAX_GUID_BYTES) } {
            Ok(g) => g,
            Err(e) => return fail(&format!("fmi2Instantiate: {}", e.describe("fmuGUID"))),
        };
        // SAFETY: null or C strings.
        let res = match unsafe { text(resource_location, MAX_LOCATION_BYTES) } {
            Ok(r) => Some(r),
            Err(TextError::Null) => None,
            Err(e) => {
                return fail(&format!(
                    "fmi2Instantiate: {}",
                    e.describe("fmuResourceLocation")
                ));
            }
        };
        create(
            logger,
            false,
            "fmi2Instantiate",
            name,
            guid,
            res,
            logging_on != 0,
        )
    });
    r.unwrap_or(std::ptr::null_mut())
}

/// The rest of an instantiation once the arguments are read: the library's binding, the model
/// the GUID / instantiation token names, the instance, its registration (`fmi3`: created by
/// fmi3InstantiateCoSimulation). Errors go to `logger` and give NULL.
pub(super) fn create(
    logger: Arc<CLogger>,
    fmi3: bool,
    func: &str,
    name: &str,
    guid: &str,
    res: Option<&str>,
    logging_on: bool,
) -> Fmi2Component {
    let fail = |msg: &str| {
        logger.log(Status::Error, "logStatusError", msg);
        std::ptr::null_mut()
    };
    let bound = match binding::current() {
        Ok(b) => b,
        Err(e) => return fail(&format!("{func}: {e}")),
    };
    let spec = match resolve_spec(bound.as_ref(), guid, res) {
        Ok(s) => s,
        Err(e) => return fail(&e.to_string()),
    };
    let sink_logger = Arc::clone(&logger);
    let sink: LogSink = Box::new(move |s, cat, msg| sink_logger.log(s, cat, msg));
    match Instance::new(spec, name, guid, res, logging_on, sink) {
        Ok(inst) => registry::register(
            logger,
            fmi3,
            Inner {
                inst,
                strings: Vec::new(),
                snapshots: HashMap::new(),
            },
        ),
        Err((sink, e)) => {
            sink(Status::Error, "logStatusError", &e.to_string());
            std::ptr::null_mut()
        }
    }
}

/// `fmi2FreeInstance`: safe with NULL, after any error, twice, and while another thread is
/// inside a call on the instance (see `ffi/registry.rs`).
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2FreeInstance(c: Fmi2Component) {
    let _ = panic_hook::guarded(|| registry::free(c));
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
    status(c, Operation::SetupExperiment, |i| {
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
    status(c, Operation::EnterInitializationMode, |i| {
        i.inst.enter_initialization_mode()
    })
}

/// `fmi2ExitInitializationMode`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2ExitInitializationMode(c: Fmi2Component) -> Fmi2Status {
    status(c, Operation::ExitInitializationMode, |i| {
        i.inst.exit_initialization_mode()
    })
}

/// `fmi2Terminate`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Terminate(c: Fmi2Component) -> Fmi2Status {
    status(c, Operation::Terminate, |i| i.inst.terminate())
}

/// `fmi2Reset`.
///
/// # Safety
/// FMI 2.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi2Reset(c: Fmi2Component) -> Fmi2Status {
    status(c, Operation::Reset, |i| i.inst.reset())
}
