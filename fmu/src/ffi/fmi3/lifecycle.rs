//! fmi3GetVersion, fmi3SetDebugLogging, fmi3InstantiateCoSimulation, fmi3FreeInstance, the
//! initialisation, fmi3DoStep, termination, reset, and the FMU-state functions (whose C
//! signatures are those of FMI 2.0: they run the FMI 2.0 bodies).

use super::super::args::{TextError, text};
use super::super::common::set_debug_logging;
use super::super::fmu_state;
use super::super::logger::{CLogger, LogFn, c_text};
use super::super::registry::status;
use super::super::types::Logger3Fn;
use super::super::{panic_hook, registry};
use crate::instance::{Operation, Status};
use crate::limits::{MAX_GUID_BYTES, MAX_LOCATION_BYTES, MAX_STRING_BYTES};
use std::ffi::{c_char, c_int, c_void};
use std::sync::Arc;

/// `fmi3Status` (a C enum: `int`).
pub type Fmi3Status = c_int;
/// `fmi3Instance`.
pub type Fmi3Instance = *mut c_void;
/// `fmi3Boolean` (C `bool`: one byte, read as a byte so that any value is defined).
pub type Fmi3Boolean = u8;

/// `fmi3GetVersion`.
#[unsafe(no_mangle)]
pub extern "C" fn fmi3GetVersion() -> *const c_char {
    c"3.0".as_ptr()
}

/// `fmi3SetDebugLogging`.
///
/// # Safety
/// FMI 3.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetDebugLogging(
    c: Fmi3Instance,
    logging_on: Fmi3Boolean,
    n: usize,
    categories: *const *const c_char,
) -> Fmi3Status {
    // SAFETY: the same contract as fmi2SetDebugLogging.
    unsafe { set_debug_logging("fmi3SetDebugLogging", c, logging_on != 0, n, categories) }
}

/// `fmi3InstantiateCoSimulation`: `resourcePath` is a directory path (FMI 3.0), not a URI;
/// event mode and intermediate variables are refused (hasEventMode = false,
/// providesIntermediateUpdate = false); early return is never used.
///
/// # Safety
/// FMI 3.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3InstantiateCoSimulation(
    instance_name: *const c_char,
    token: *const c_char,
    resource_path: *const c_char,
    _visible: Fmi3Boolean,
    logging_on: Fmi3Boolean,
    event_mode_used: Fmi3Boolean,
    _early_return_allowed: Fmi3Boolean,
    _required_intermediate: *const u32,
    n_required_intermediate: usize,
    env: *mut c_void,
    log_message: Option<Logger3Fn>,
    _intermediate_update: *const c_void,
) -> Fmi3Instance {
    let r = panic_hook::guarded(|| {
        // SAFETY: null or C strings.
        let name = unsafe { text(instance_name, MAX_STRING_BYTES) };
        let logger = Arc::new(CLogger {
            f: log_message.map(LogFn::V3),
            env,
            name: c_text(name.unwrap_or("")),
        });
        let fail = |msg: &str| {
            logger.log(Status::Error, "logStatusError", msg);
            std::ptr::null_mut()
        };
        const F: &str = "fmi3InstantiateCoSimulation";
        let name = match name {
            Ok(n) => n,
            Err(e) => return fail(&format!("{F}: {}", e.describe("instanceName"))),
        };
        if event_mode_used != 0 {
            return fail(&format!(
                "{F}: eventModeUsed = true, but this FMU has no event mode (hasEventMode = false)"
            ));
        }
        if n_required_intermediate != 0 {
            return fail(&format!(
                "{F}: {n_required_intermediate} required intermediate variables, but this FMU provides no intermediate update (providesIntermediateUpdate = false)"
            ));
        }
        // SAFETY: null or C strings.
        let token = match unsafe { text(token, MAX_GUID_BYTES) } {
            Ok(g) => g,
            Err(e) => return fail(&format!("{F}: {}", e.describe("instantiationToken"))),
        };
        // SAFETY: null or C strings.
        let res = match unsafe { text(resource_path, MAX_LOCATION_BYTES) } {
            // A path: '%' is escaped so that the location is read literally.
            Ok(r) => Some(r.replace('%', "%25")),
            Err(TextError::Null) => None,
            Err(e) => return fail(&format!("{F}: {}", e.describe("resourcePath"))),
        };
        super::super::common::create(
            logger,
            true,
            F,
            name,
            token,
            res.as_deref(),
            logging_on != 0,
        )
    });
    r.unwrap_or(std::ptr::null_mut())
}

/// `fmi3FreeInstance`.
///
/// # Safety
/// FMI 3.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3FreeInstance(c: Fmi3Instance) {
    let _ = panic_hook::guarded(|| registry::free(c));
}

/// `fmi3EnterInitializationMode`: the experiment set-up of FMI 2.0's fmi2SetupExperiment, then
/// Initialization Mode; if the set-up is refused the instance stays in *Instantiated*.
///
/// # Safety
/// FMI 3.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3EnterInitializationMode(
    c: Fmi3Instance,
    _tolerance_defined: Fmi3Boolean,
    _tolerance: f64,
    start_time: f64,
    stop_time_defined: Fmi3Boolean,
    stop_time: f64,
) -> Fmi3Status {
    status(c, "fmi3EnterInitializationMode", |i| {
        if let Err(s) = i.inst.check_as(
            Operation::EnterInitializationMode,
            "fmi3EnterInitializationMode",
        ) {
            return s;
        }
        let stop = (stop_time_defined != 0).then_some(stop_time);
        match i.inst.setup_experiment(start_time, stop) {
            Status::Ok => i.inst.enter_initialization_mode(),
            s => s,
        }
    })
}

/// `fmi3ExitInitializationMode`: into Step Mode.
///
/// # Safety
/// FMI 3.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3ExitInitializationMode(c: Fmi3Instance) -> Fmi3Status {
    status(c, "fmi3ExitInitializationMode", |i| {
        i.inst.exit_initialization_mode()
    })
}

/// `fmi3Terminate`.
///
/// # Safety
/// FMI 3.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3Terminate(c: Fmi3Instance) -> Fmi3Status {
    status(c, "fmi3Terminate", |i| i.inst.terminate())
}

/// `fmi3Reset`.
///
/// # Safety
/// FMI 3.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3Reset(c: Fmi3Instance) -> Fmi3Status {
    status(c, "fmi3Reset", |i| i.inst.reset())
}

/// Write `v` through `p` when the master passed a pointer.
///
/// # Safety
/// `p` is null or points to a writable `T`.
unsafe fn put<T>(p: *mut T, v: T) {
    if !p.is_null() {
        // SAFETY: non-null pointer to the master's variable.
        unsafe { *p = v };
    }
}

/// `fmi3DoStep`: the FMI 2.0 step; `eventHandlingNeeded`, `terminateSimulation` and
/// `earlyReturn` are always false (no event mode; the FMU never asks to stop: the truth outputs
/// say why it stopped; steps are synchronous), `lastSuccessfulTime` is the end of the step, or
/// the unchanged time of a refused one.
///
/// # Safety
/// FMI 3.0 calling conventions.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn fmi3DoStep(
    c: Fmi3Instance,
    current_communication_point: f64,
    communication_step_size: f64,
    _no_set_fmu_state_prior: Fmi3Boolean,
    event_handling_needed: *mut Fmi3Boolean,
    terminate_simulation: *mut Fmi3Boolean,
    early_return: *mut Fmi3Boolean,
    last_successful_time: *mut f64,
) -> Fmi3Status {
    status(c, "fmi3DoStep", |i| {
        let s = i
            .inst
            .do_step(current_communication_point, communication_step_size);
        // SAFETY: each pointer is null (not written) or the master's variable.
        unsafe {
            put(event_handling_needed, 0);
            put(terminate_simulation, 0);
            put(early_return, 0);
            put(last_successful_time, i.inst.last_successful_time());
        }
        s
    })
}

/// `fmi3GetFMUState`.
///
/// # Safety
/// FMI 3.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetFMUState(c: Fmi3Instance, state: *mut *mut c_void) -> Fmi3Status {
    // SAFETY: the same contract as fmi2GetFMUstate.
    unsafe { fmu_state::get_fmu_state("fmi3GetFMUState", c, state) }
}

/// `fmi3SetFMUState`.
///
/// # Safety
/// FMI 3.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetFMUState(c: Fmi3Instance, state: *mut c_void) -> Fmi3Status {
    // SAFETY: the same contract as fmi2SetFMUstate.
    unsafe { fmu_state::set_fmu_state("fmi3SetFMUState", c, state) }
}

/// `fmi3FreeFMUState`.
///
/// # Safety
/// FMI 3.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3FreeFMUState(c: Fmi3Instance, state: *mut *mut c_void) -> Fmi3Status {
    // SAFETY: the same contract as fmi2FreeFMUstate.
    unsafe { fmu_state::free_fmu_state("fmi3FreeFMUState", c, state) }
}

/// `fmi3SerializedFMUStateSize`.
///
/// # Safety
/// FMI 3.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SerializedFMUStateSize(
    c: Fmi3Instance,
    state: *mut c_void,
    size: *mut usize,
) -> Fmi3Status {
    // SAFETY: the same contract as fmi2SerializedFMUstateSize.
    unsafe { fmu_state::serialized_size("fmi3SerializedFMUStateSize", c, state, size) }
}

/// `fmi3SerializeFMUState`.
///
/// # Safety
/// FMI 3.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SerializeFMUState(
    c: Fmi3Instance,
    state: *mut c_void,
    bytes: *mut u8,
    size: usize,
) -> Fmi3Status {
    // SAFETY: the same contract as fmi2SerializeFMUstate.
    unsafe { fmu_state::serialize("fmi3SerializeFMUState", c, state, bytes, size) }
}

/// `fmi3DeserializeFMUState`.
///
/// # Safety
/// FMI 3.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3DeserializeFMUState(
    c: Fmi3Instance,
    bytes: *const u8,
    size: usize,
    state: *mut *mut c_void,
) -> Fmi3Status {
    // SAFETY: the same contract as fmi2DeSerializeFMUstate.
    unsafe { fmu_state::deserialize("fmi3DeserializeFMUState", c, bytes, size, state) }
}
