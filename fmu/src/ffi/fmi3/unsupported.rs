//! The FMI 3.0 functions of capabilities this FMU does not have: each is exported (a master may
//! load every symbol) and answers `fmi3Error` with a logged reason, or NULL for the model-exchange
//! and scheduled-execution instantiation functions.

use super::super::args::slice;
use super::super::logger::{CLogger, LogFn};
use super::super::panic_hook;
use super::super::registry::status;
use super::super::types::Logger3Fn;
use super::lifecycle::{Fmi3Boolean, Fmi3Instance, Fmi3Status};
use crate::instance::{Operation, Status};
use crate::limits::MAX_VALUE_REFS;
use std::ffi::{CString, c_char, c_int, c_void};

/// Log `why` through the master's logger (if any) for an instantiation this FMU refuses.
fn refuse_instantiation(env: *mut c_void, log: Option<Logger3Fn>, func: &str, why: &str) {
    let logger = CLogger {
        f: log.map(LogFn::V3),
        env,
        name: CString::default(),
    };
    logger.log(
        Status::Error,
        "logStatusError",
        &format!("{func}: {why} is not supported by this FMU; it is a co-simulation FMU (fmi3InstantiateCoSimulation)"),
    );
}

/// `fmi3InstantiateModelExchange`: NULL (co-simulation only).
///
/// # Safety
/// FMI 3.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3InstantiateModelExchange(
    _instance_name: *const c_char,
    _token: *const c_char,
    _resource_path: *const c_char,
    _visible: Fmi3Boolean,
    _logging_on: Fmi3Boolean,
    env: *mut c_void,
    log_message: Option<Logger3Fn>,
) -> Fmi3Instance {
    let _ = panic_hook::guarded(|| {
        refuse_instantiation(
            env,
            log_message,
            "fmi3InstantiateModelExchange",
            "model exchange",
        )
    });
    std::ptr::null_mut()
}

/// `fmi3InstantiateScheduledExecution`: NULL (co-simulation only).
///
/// # Safety
/// FMI 3.0 calling conventions.
#[unsafe(no_mangle)]
#[allow(clippy::too_many_arguments)]
pub unsafe extern "C" fn fmi3InstantiateScheduledExecution(
    _instance_name: *const c_char,
    _token: *const c_char,
    _resource_path: *const c_char,
    _visible: Fmi3Boolean,
    _logging_on: Fmi3Boolean,
    env: *mut c_void,
    log_message: Option<Logger3Fn>,
    _clock_update: *const c_void,
    _lock_preemption: *const c_void,
    _unlock_preemption: *const c_void,
) -> Fmi3Instance {
    let _ = panic_hook::guarded(|| {
        refuse_instantiation(
            env,
            log_message,
            "fmi3InstantiateScheduledExecution",
            "scheduled execution",
        )
    });
    std::ptr::null_mut()
}

/// fmi3Error with "`func`: `what` is not supported by this FMU".
fn refuse(c: Fmi3Instance, func: &'static str, what: &'static str) -> Fmi3Status {
    status(c, func, |i| {
        i.inst
            .error(&format!("{func}: {what} is not supported by this FMU"))
    })
}

macro_rules! unsupported {
    ($($name:ident ( $($arg:ident : $t:ty),* ) => $what:literal;)*) => {
        $(
            #[doc = concat!("`", stringify!($name), "`: not supported (", $what, ").")]
            ///
            /// # Safety
            /// FMI 3.0 calling conventions.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn $name(c: Fmi3Instance $(, $arg: $t)*) -> Fmi3Status {
                $(let _ = $arg;)*
                refuse(c, stringify!($name), $what)
            }
        )*
    };
}

unsupported! {
    fmi3EnterEventMode() => "event mode (hasEventMode = false)";
    fmi3EnterStepMode() => "event mode (hasEventMode = false)";
    fmi3EnterConfigurationMode() => "configuration mode (the structural parameter is fixed by the model)";
    fmi3ExitConfigurationMode() => "configuration mode (the structural parameter is fixed by the model)";
    fmi3GetNumberOfVariableDependencies(_vr: u32, _n: *mut usize) => "run-time dependency information (providesPerElementDependencies = false; see ModelStructure)";
    fmi3GetVariableDependencies(_dependent: u32, _ei: *mut usize, _independents: *mut u32, _eii: *mut usize, _kinds: *mut c_int, _n: usize) => "run-time dependency information (providesPerElementDependencies = false; see ModelStructure)";
    fmi3GetDirectionalDerivative(_u: *const u32, _nu: usize, _k: *const u32, _nk: usize, _seed: *const f64, _ns: usize, _sens: *mut f64, _nsens: usize) => "directional derivatives (providesDirectionalDerivatives = false)";
    fmi3GetAdjointDerivative(_u: *const u32, _nu: usize, _k: *const u32, _nk: usize, _seed: *const f64, _ns: usize, _sens: *mut f64, _nsens: usize) => "adjoint derivatives (providesAdjointDerivatives = false)";
    fmi3GetOutputDerivatives(_vr: *const u32, _nvr: usize, _orders: *const i32, _values: *mut f64, _n: usize) => "output derivatives (maxOutputDerivativeOrder = 0)";
    fmi3GetClock(_vr: *const u32, _nvr: usize, _values: *mut Fmi3Boolean) => "clocks (the model has none)";
    fmi3SetClock(_vr: *const u32, _nvr: usize, _values: *const Fmi3Boolean) => "clocks (the model has none)";
    fmi3GetIntervalDecimal(_vr: *const u32, _nvr: usize, _i: *mut f64, _q: *mut c_int) => "clocks (the model has none)";
    fmi3GetIntervalFraction(_vr: *const u32, _nvr: usize, _counters: *mut u64, _r: *mut u64, _q: *mut c_int) => "clocks (the model has none)";
    fmi3GetShiftDecimal(_vr: *const u32, _nvr: usize, _s: *mut f64) => "clocks (the model has none)";
    fmi3GetShiftFraction(_vr: *const u32, _nvr: usize, _counters: *mut u64, _r: *mut u64) => "clocks (the model has none)";
    fmi3SetIntervalDecimal(_vr: *const u32, _nvr: usize, _i: *const f64) => "clocks (the model has none)";
    fmi3SetIntervalFraction(_vr: *const u32, _nvr: usize, _counters: *const u64, _r: *const u64) => "clocks (the model has none)";
    fmi3SetShiftDecimal(_vr: *const u32, _nvr: usize, _s: *const f64) => "clocks (the model has none)";
    fmi3SetShiftFraction(_vr: *const u32, _nvr: usize, _counters: *const u64, _r: *const u64) => "clocks (the model has none)";
    fmi3EvaluateDiscreteStates() => "event mode (providesEvaluateDiscreteStates = false)";
    fmi3UpdateDiscreteStates(_a: *mut Fmi3Boolean, _b: *mut Fmi3Boolean, _nominals_changed: *mut Fmi3Boolean, _d: *mut Fmi3Boolean, _e: *mut Fmi3Boolean, _t: *mut f64) => "event mode (hasEventMode = false)";
    fmi3EnterContinuousTimeMode() => "model exchange";
    fmi3CompletedIntegratorStep(_no_prior: Fmi3Boolean, _enter: *mut Fmi3Boolean, _term: *mut Fmi3Boolean) => "model exchange";
    fmi3SetTime(_t: f64) => "model exchange";
    fmi3SetContinuousStates(_x: *const f64, _n: usize) => "model exchange";
    fmi3GetContinuousStateDerivatives(_dx: *mut f64, _n: usize) => "model exchange";
    fmi3GetEventIndicators(_z: *mut f64, _n: usize) => "model exchange";
    fmi3GetContinuousStates(_x: *mut f64, _n: usize) => "model exchange";
    fmi3GetNominalsOfContinuousStates(_x: *mut f64, _n: usize) => "model exchange";
    fmi3GetNumberOfEventIndicators(_n: *mut usize) => "model exchange";
    fmi3GetNumberOfContinuousStates(_n: *mut usize) => "model exchange";
    fmi3ActivateModelPartition(_clock: u32, _t: f64) => "scheduled execution";
}

/// A getter or setter of a type this FMU has no variables of: allowed (and a no-op) for zero
/// references, else fmi3Error naming the first reference.
fn no_variables(
    c: Fmi3Instance,
    func: &'static str,
    type_name: &'static str,
    get: bool,
    vr: *const u32,
    nvr: usize,
) -> Fmi3Status {
    status(c, func, |i| {
        let op = if get {
            Operation::GetReal
        } else {
            Operation::SetReal
        };
        if let Err(s) = i.inst.check_as(op, func) {
            return s;
        }
        // SAFETY: the master passes `nvr` references (bounded first).
        match unsafe { slice(vr, nvr, MAX_VALUE_REFS) } {
            Some([]) => Status::Ok,
            Some([first, ..]) => i.inst.error(&format!(
                "{func}: value reference {first} is not a {type_name} variable (this FMU has no {type_name} variables)"
            )),
            None => i.inst.error(&format!(
                "{func}: valueReferences is a null pointer, or nValueReferences = {nvr} is over the limit ({MAX_VALUE_REFS})"
            )),
        }
    })
}

macro_rules! no_type {
    ($($get:ident, $set:ident, $t:ty, $name:literal;)*) => {
        $(
            #[doc = concat!("`", stringify!($get), "`: this FMU has no ", $name, " variables.")]
            ///
            /// # Safety
            /// FMI 3.0 calling conventions.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn $get(
                c: Fmi3Instance,
                vr: *const u32,
                nvr: usize,
                _values: *mut $t,
                _n_values: usize,
            ) -> Fmi3Status {
                no_variables(c, stringify!($get), $name, true, vr, nvr)
            }

            #[doc = concat!("`", stringify!($set), "`: this FMU has no ", $name, " variables.")]
            ///
            /// # Safety
            /// FMI 3.0 calling conventions.
            #[unsafe(no_mangle)]
            pub unsafe extern "C" fn $set(
                c: Fmi3Instance,
                vr: *const u32,
                nvr: usize,
                _values: *const $t,
                _n_values: usize,
            ) -> Fmi3Status {
                no_variables(c, stringify!($set), $name, false, vr, nvr)
            }
        )*
    };
}

no_type! {
    fmi3GetFloat32, fmi3SetFloat32, f32, "Float32";
    fmi3GetInt8, fmi3SetInt8, i8, "Int8";
    fmi3GetUInt8, fmi3SetUInt8, u8, "UInt8";
    fmi3GetInt16, fmi3SetInt16, i16, "Int16";
    fmi3GetUInt16, fmi3SetUInt16, u16, "UInt16";
    fmi3GetUInt32, fmi3SetUInt32, u32, "UInt32";
}

/// `fmi3GetBinary`: this FMU has no Binary variables.
///
/// # Safety
/// FMI 3.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3GetBinary(
    c: Fmi3Instance,
    vr: *const u32,
    nvr: usize,
    _sizes: *mut usize,
    _values: *mut *const u8,
    _n_values: usize,
) -> Fmi3Status {
    no_variables(c, "fmi3GetBinary", "Binary", true, vr, nvr)
}

/// `fmi3SetBinary`: this FMU has no Binary variables.
///
/// # Safety
/// FMI 3.0 calling conventions.
#[unsafe(no_mangle)]
pub unsafe extern "C" fn fmi3SetBinary(
    c: Fmi3Instance,
    vr: *const u32,
    nvr: usize,
    _sizes: *const usize,
    _values: *const *const u8,
    _n_values: usize,
) -> Fmi3Status {
    no_variables(c, "fmi3SetBinary", "Binary", false, vr, nvr)
}
