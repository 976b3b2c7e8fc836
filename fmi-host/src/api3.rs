//! The fmi3 functions of a loaded FMU library ([`Api3`]), and the log callback the host passes
//! to the fmi3 instantiation functions ([`host_logger3`]).
//!
//! The signatures are those of `fmi3FunctionTypes.h` (FMI 3.0): `fmi3Status` and the C enums
//! (`fmi3DependencyKind`, `fmi3IntervalQualifier`) are `int`, `fmi3Boolean` and `fmi3Clock` are a
//! one-byte C `bool` (here `u8`, so that any byte the FMU writes is a defined value),
//! `fmi3ValueReference` is `uint32_t`, `fmi3Byte` is `uint8_t`, and the log callback
//! (`fmi3LogMessageCallback`) is *not* variadic: its message is plain text, not a format.
//! All 75 functions are loaded (an FMI 3.0 library must export every one), so a missing symbol
//! is an error when the library is loaded, not a crash later.

#![allow(non_snake_case)]

use crate::error::{HostError, Result};
use crate::instance::Message;
use std::ffi::{CStr, c_char, c_int, c_void};
use std::path::Path;
use std::sync::Mutex;

/// An fmi3Instance.
pub type Inst3 = *mut c_void;
/// An fmi3FMUState.
pub type State3 = *mut c_void;
/// `fmi3LogMessageCallback`: environment, status, category, message.
pub type Logger3 = extern "C" fn(*mut c_void, c_int, *const c_char, *const c_char);
/// `fmi3IntermediateUpdateCallback`.
pub type IntermediateUpdate3 = extern "C" fn(*mut c_void, f64, u8, u8, u8, u8, *mut u8, *mut f64);
/// `fmi3ClockUpdateCallback`.
pub type ClockUpdate3 = extern "C" fn(*mut c_void);
/// `fmi3LockPreemptionCallback` and `fmi3UnlockPreemptionCallback`.
pub type Preemption3 = extern "C" fn();

/// What [`host_logger3`] expects as its instance environment: the instance's message buffer.
pub type Log3 = Mutex<Vec<Message>>;

/// The host's `fmi3LogMessageCallback`: appends (status, category, message) to the [`Log3`] the
/// instance environment points to (nothing when the environment or the message is null).
pub extern "C" fn host_logger3(
    env: *mut c_void,
    status: c_int,
    category: *const c_char,
    message: *const c_char,
) {
    if env.is_null() || message.is_null() {
        return;
    }
    let text = |p: *const c_char| {
        if p.is_null() {
            String::new()
        } else {
            // SAFETY: a non-null C string from the FMU, valid during the call.
            unsafe { CStr::from_ptr(p) }.to_string_lossy().into_owned()
        }
    };
    // SAFETY: env is the `Log3` the host passed at instantiation and keeps alive while the
    // instance exists.
    let log = unsafe { &*(env as *const Log3) };
    if let Ok(mut l) = log.lock() {
        l.push(Message {
            status,
            category: text(category),
            text: text(message),
        });
    }
}

macro_rules! api3 {
    ($($name:ident : $ty:ty;)*) => {
        /// The 75 fmi3 functions of a loaded FMU library.
        #[allow(dead_code, missing_docs)]
        pub struct Api3 {
            /// The loaded library (`None`: the functions linked into this program).
            _lib: Option<libloading::Library>,
            $(pub $name: $ty,)*
        }

        impl Api3 {
            /// Load the library at `path` and every fmi3 function of it.
            pub fn load(path: &Path) -> Result<Api3> {
                // SAFETY: loading the FMU library runs no initialisers with preconditions.
                let lib = unsafe { libloading::Library::new(path) }.map_err(|source| HostError::Load {
                    path: path.display().to_string(),
                    source,
                })?;
                $(
                    // SAFETY: the symbol has the FMI 3.0 signature (fmi3FunctionTypes.h).
                    let $name: $ty = *unsafe { lib.get::<$ty>(concat!(stringify!($name), "\0").as_bytes()) }
                        .map_err(|source| HostError::Symbol {
                            path: path.display().to_string(),
                            symbol: stringify!($name),
                            source,
                        })?;
                )*
                Ok(Api3 { _lib: Some(lib), $($name,)* })
            }

            /// The fmi3 functions of the `entrynav-fmu` crate linked into this program, taken
            /// with the FMI 3.0 signatures as [`Api3::load`] takes them from a library: the host
            /// drives the FMU code in process, with no packed FMU (tests of the host's tools).
            pub fn linked() -> Api3 {
                $(
                    // SAFETY: entrynav-fmu exports this function with the FMI 3.0 signature
                    // `$ty` (its own Rust types are the same C types), as a loaded library does.
                    let $name: $ty = unsafe {
                        std::mem::transmute::<*const (), $ty>(entrynav_fmu::ffi::$name as *const ())
                    };
                )*
                Api3 { _lib: None, $($name,)* }
            }

            /// The names of the functions, in the order they are loaded.
            pub const FUNCTIONS: &'static [&'static str] = &[$(stringify!($name),)*];
        }
    };
}

api3! {
    // Common functions.
    fmi3GetVersion: unsafe extern "C" fn() -> *const c_char;
    fmi3SetDebugLogging: unsafe extern "C" fn(Inst3, u8, usize, *const *const c_char) -> c_int;
    fmi3InstantiateModelExchange: unsafe extern "C" fn(*const c_char, *const c_char, *const c_char, u8, u8, *mut c_void, Option<Logger3>) -> Inst3;
    fmi3InstantiateCoSimulation: unsafe extern "C" fn(*const c_char, *const c_char, *const c_char, u8, u8, u8, u8, *const u32, usize, *mut c_void, Option<Logger3>, Option<IntermediateUpdate3>) -> Inst3;
    fmi3InstantiateScheduledExecution: unsafe extern "C" fn(*const c_char, *const c_char, *const c_char, u8, u8, *mut c_void, Option<Logger3>, Option<ClockUpdate3>, Option<Preemption3>, Option<Preemption3>) -> Inst3;
    fmi3FreeInstance: unsafe extern "C" fn(Inst3);
    fmi3EnterInitializationMode: unsafe extern "C" fn(Inst3, u8, f64, f64, u8, f64) -> c_int;
    fmi3ExitInitializationMode: unsafe extern "C" fn(Inst3) -> c_int;
    fmi3EnterEventMode: unsafe extern "C" fn(Inst3) -> c_int;
    fmi3Terminate: unsafe extern "C" fn(Inst3) -> c_int;
    fmi3Reset: unsafe extern "C" fn(Inst3) -> c_int;
    // Getters.
    fmi3GetFloat32: unsafe extern "C" fn(Inst3, *const u32, usize, *mut f32, usize) -> c_int;
    fmi3GetFloat64: unsafe extern "C" fn(Inst3, *const u32, usize, *mut f64, usize) -> c_int;
    fmi3GetInt8: unsafe extern "C" fn(Inst3, *const u32, usize, *mut i8, usize) -> c_int;
    fmi3GetUInt8: unsafe extern "C" fn(Inst3, *const u32, usize, *mut u8, usize) -> c_int;
    fmi3GetInt16: unsafe extern "C" fn(Inst3, *const u32, usize, *mut i16, usize) -> c_int;
    fmi3GetUInt16: unsafe extern "C" fn(Inst3, *const u32, usize, *mut u16, usize) -> c_int;
    fmi3GetInt32: unsafe extern "C" fn(Inst3, *const u32, usize, *mut i32, usize) -> c_int;
    fmi3GetUInt32: unsafe extern "C" fn(Inst3, *const u32, usize, *mut u32, usize) -> c_int;
    fmi3GetInt64: unsafe extern "C" fn(Inst3, *const u32, usize, *mut i64, usize) -> c_int;
    fmi3GetUInt64: unsafe extern "C" fn(Inst3, *const u32, usize, *mut u64, usize) -> c_int;
    fmi3GetBoolean: unsafe extern "C" fn(Inst3, *const u32, usize, *mut u8, usize) -> c_int;
    fmi3GetString: unsafe extern "C" fn(Inst3, *const u32, usize, *mut *const c_char, usize) -> c_int;
    fmi3GetBinary: unsafe extern "C" fn(Inst3, *const u32, usize, *mut usize, *mut *const u8, usize) -> c_int;
    fmi3GetClock: unsafe extern "C" fn(Inst3, *const u32, usize, *mut u8) -> c_int;
    // Setters.
    fmi3SetFloat32: unsafe extern "C" fn(Inst3, *const u32, usize, *const f32, usize) -> c_int;
    fmi3SetFloat64: unsafe extern "C" fn(Inst3, *const u32, usize, *const f64, usize) -> c_int;
    fmi3SetInt8: unsafe extern "C" fn(Inst3, *const u32, usize, *const i8, usize) -> c_int;
    fmi3SetUInt8: unsafe extern "C" fn(Inst3, *const u32, usize, *const u8, usize) -> c_int;
    fmi3SetInt16: unsafe extern "C" fn(Inst3, *const u32, usize, *const i16, usize) -> c_int;
    fmi3SetUInt16: unsafe extern "C" fn(Inst3, *const u32, usize, *const u16, usize) -> c_int;
    fmi3SetInt32: unsafe extern "C" fn(Inst3, *const u32, usize, *const i32, usize) -> c_int;
    fmi3SetUInt32: unsafe extern "C" fn(Inst3, *const u32, usize, *const u32, usize) -> c_int;
    fmi3SetInt64: unsafe extern "C" fn(Inst3, *const u32, usize, *const i64, usize) -> c_int;
    fmi3SetUInt64: unsafe extern "C" fn(Inst3, *const u32, usize, *const u64, usize) -> c_int;
    fmi3SetBoolean: unsafe extern "C" fn(Inst3, *const u32, usize, *const u8, usize) -> c_int;
    fmi3SetString: unsafe extern "C" fn(Inst3, *const u32, usize, *const *const c_char, usize) -> c_int;
    fmi3SetBinary: unsafe extern "C" fn(Inst3, *const u32, usize, *const usize, *const *const u8, usize) -> c_int;
    fmi3SetClock: unsafe extern "C" fn(Inst3, *const u32, usize, *const u8) -> c_int;
    // Dependencies.
    fmi3GetNumberOfVariableDependencies: unsafe extern "C" fn(Inst3, u32, *mut usize) -> c_int;
    fmi3GetVariableDependencies: unsafe extern "C" fn(Inst3, u32, *mut usize, *mut u32, *mut usize, *mut c_int, usize) -> c_int;
    // FMU states.
    fmi3GetFMUState: unsafe extern "C" fn(Inst3, *mut State3) -> c_int;
    fmi3SetFMUState: unsafe extern "C" fn(Inst3, State3) -> c_int;
    fmi3FreeFMUState: unsafe extern "C" fn(Inst3, *mut State3) -> c_int;
    fmi3SerializedFMUStateSize: unsafe extern "C" fn(Inst3, State3, *mut usize) -> c_int;
    fmi3SerializeFMUState: unsafe extern "C" fn(Inst3, State3, *mut u8, usize) -> c_int;
    fmi3DeserializeFMUState: unsafe extern "C" fn(Inst3, *const u8, usize, *mut State3) -> c_int;
    // Derivatives.
    fmi3GetDirectionalDerivative: unsafe extern "C" fn(Inst3, *const u32, usize, *const u32, usize, *const f64, usize, *mut f64, usize) -> c_int;
    fmi3GetAdjointDerivative: unsafe extern "C" fn(Inst3, *const u32, usize, *const u32, usize, *const f64, usize, *mut f64, usize) -> c_int;
    // Configuration mode.
    fmi3EnterConfigurationMode: unsafe extern "C" fn(Inst3) -> c_int;
    fmi3ExitConfigurationMode: unsafe extern "C" fn(Inst3) -> c_int;
    // Clocks.
    fmi3GetIntervalDecimal: unsafe extern "C" fn(Inst3, *const u32, usize, *mut f64, *mut c_int) -> c_int;
    fmi3GetIntervalFraction: unsafe extern "C" fn(Inst3, *const u32, usize, *mut u64, *mut u64, *mut c_int) -> c_int;
    fmi3GetShiftDecimal: unsafe extern "C" fn(Inst3, *const u32, usize, *mut f64) -> c_int;
    fmi3GetShiftFraction: unsafe extern "C" fn(Inst3, *const u32, usize, *mut u64, *mut u64) -> c_int;
    fmi3SetIntervalDecimal: unsafe extern "C" fn(Inst3, *const u32, usize, *const f64) -> c_int;
    fmi3SetIntervalFraction: unsafe extern "C" fn(Inst3, *const u32, usize, *const u64, *const u64) -> c_int;
    fmi3SetShiftDecimal: unsafe extern "C" fn(Inst3, *const u32, usize, *const f64) -> c_int;
    fmi3SetShiftFraction: unsafe extern "C" fn(Inst3, *const u32, usize, *const u64, *const u64) -> c_int;
    fmi3EvaluateDiscreteStates: unsafe extern "C" fn(Inst3) -> c_int;
    fmi3UpdateDiscreteStates: unsafe extern "C" fn(Inst3, *mut u8, *mut u8, *mut u8, *mut u8, *mut u8, *mut f64) -> c_int;
    // Model exchange.
    fmi3EnterContinuousTimeMode: unsafe extern "C" fn(Inst3) -> c_int;
    fmi3CompletedIntegratorStep: unsafe extern "C" fn(Inst3, u8, *mut u8, *mut u8) -> c_int;
    fmi3SetTime: unsafe extern "C" fn(Inst3, f64) -> c_int;
    fmi3SetContinuousStates: unsafe extern "C" fn(Inst3, *const f64, usize) -> c_int;
    fmi3GetContinuousStateDerivatives: unsafe extern "C" fn(Inst3, *mut f64, usize) -> c_int;
    fmi3GetEventIndicators: unsafe extern "C" fn(Inst3, *mut f64, usize) -> c_int;
    fmi3GetContinuousStates: unsafe extern "C" fn(Inst3, *mut f64, usize) -> c_int;
    fmi3GetNominalsOfContinuousStates: unsafe extern "C" fn(Inst3, *mut f64, usize) -> c_int;
    fmi3GetNumberOfEventIndicators: unsafe extern "C" fn(Inst3, *mut usize) -> c_int;
    fmi3GetNumberOfContinuousStates: unsafe extern "C" fn(Inst3, *mut usize) -> c_int;
    // Co-simulation.
    fmi3EnterStepMode: unsafe extern "C" fn(Inst3) -> c_int;
    fmi3GetOutputDerivatives: unsafe extern "C" fn(Inst3, *const u32, usize, *const i32, *mut f64, usize) -> c_int;
    fmi3DoStep: unsafe extern "C" fn(Inst3, f64, f64, u8, *mut u8, *mut u8, *mut u8, *mut f64) -> c_int;
    // Scheduled execution.
    fmi3ActivateModelPartition: unsafe extern "C" fn(Inst3, u32, f64) -> c_int;
}

#[cfg(test)]
mod tests {
    use super::Api3;

    #[test]
    fn all_75_fmi3_functions_are_loaded_once() {
        let mut names = Api3::FUNCTIONS.to_vec();
        assert_eq!(names.len(), 75);
        names.sort_unstable();
        names.dedup();
        assert_eq!(names.len(), 75);
        assert!(names.iter().all(|n| n.starts_with("fmi3")));
    }
}
