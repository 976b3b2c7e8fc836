//! The fmi2 functions of a loaded FMU library ([`Api`]), and the callbacks the host passes to
//! `fmi2Instantiate` ([`Callbacks`], whose logger appends to a [`Log`]).
//!
//! The logger is declared without the C varargs (stable Rust cannot define variadic functions);
//! on x86-64 System V a variadic call to it is ABI-compatible, and our FMUs never pass format
//! arguments (messages are pre-formatted, `%` escaped as `%%`).

#![allow(non_snake_case)]

use crate::error::{HostError, Result};
use crate::instance::Message;
use std::ffi::{CStr, c_char, c_int, c_void};
use std::path::Path;
use std::sync::Mutex;

/// An fmi2Component.
pub type Comp = *mut c_void;
/// The host's logger, without C varargs (see the module documentation).
pub type HostLogger =
    extern "C" fn(*mut c_void, *const c_char, c_int, *const c_char, *const c_char);

/// fmi2CallbackFunctions as the host passes them.
#[repr(C)]
pub struct Callbacks {
    /// Logger.
    pub logger: Option<HostLogger>,
    /// Unused by our FMUs.
    pub allocate: Option<extern "C" fn(usize, usize) -> *mut c_void>,
    /// Unused by our FMUs.
    pub free: Option<extern "C" fn(*mut c_void)>,
    /// Unused by our FMUs.
    pub step_finished: Option<extern "C" fn(*mut c_void, c_int)>,
    /// Passed back to the logger: the instance's message buffer.
    pub env: *mut c_void,
}

/// What the host's logger expects as its environment: the instance's message buffer.
pub type Log = Mutex<Vec<Message>>;

/// The host's `fmi2CallbackLogger`: appends the message (`%%` read as `%`) to the [`Log`] the
/// environment points to (nothing when the environment or the message is null).
pub(crate) extern "C" fn host_logger(
    env: *mut c_void,
    _name: *const c_char,
    status: c_int,
    category: *const c_char,
    msg: *const c_char,
) {
    if env.is_null() || msg.is_null() {
        return;
    }
    // SAFETY: env is the `Log` the host passed in Callbacks and keeps alive while the instance
    // exists; category and msg are null or C strings from the FMU.
    let (log, category, text) = unsafe {
        (
            &*(env as *const Log),
            if category.is_null() {
                String::new()
            } else {
                CStr::from_ptr(category).to_string_lossy().into_owned()
            },
            CStr::from_ptr(msg).to_string_lossy().replace("%%", "%"),
        )
    };
    if let Ok(mut l) = log.lock() {
        l.push(Message {
            status,
            category,
            text,
        });
    }
}

macro_rules! api {
    ($($name:ident : $ty:ty;)*) => {
        /// The 34 fmi2 functions of a loaded FMU library.
        #[allow(dead_code, missing_docs)]
        pub struct Api {
            /// The loaded library (`None`: the functions linked into this program).
            _lib: Option<libloading::Library>,
            $(pub $name: $ty,)*
        }

        impl Api {
            /// Load the library at `path` and every fmi2 function of it.
            pub fn load(path: &Path) -> Result<Api> {
                // SAFETY: loading the FMU library runs no initialisers with preconditions.
                let lib = unsafe { libloading::Library::new(path) }.map_err(|source| HostError::Load {
                    path: path.display().to_string(),
                    source,
                })?;
                $(
                    // SAFETY: the symbol has the FMI 2.0 signature.
                    let $name: $ty = *unsafe { lib.get::<$ty>(concat!(stringify!($name), "\0").as_bytes()) }
                        .map_err(|source| HostError::Symbol {
                            path: path.display().to_string(),
                            symbol: stringify!($name),
                            source,
                        })?;
                )*
                Ok(Api { _lib: Some(lib), $($name,)* })
            }

            /// The fmi2 functions of the `entrynav-fmu` crate linked into this program, taken
            /// with the FMI 2.0 signatures as [`Api::load`] takes them from a library: the host
            /// drives the FMU code in process, with no packed FMU (tests of the host's tools).
            pub fn linked() -> Api {
                $(
                    // SAFETY: entrynav-fmu exports this function with the FMI 2.0 signature
                    // `$ty` (its own Rust types are the same C types), as a loaded library does.
                    let $name: $ty = unsafe {
                        std::mem::transmute::<*const (), $ty>(entrynav_fmu::ffi::$name as *const ())
                    };
                )*
                Api { _lib: None, $($name,)* }
            }

            /// The names of the functions, in the order they are loaded.
            pub const FUNCTIONS: &'static [&'static str] = &[$(stringify!($name),)*];
        }
    };
}

api! {
    fmi2GetTypesPlatform: unsafe extern "C" fn() -> *const c_char;
    fmi2GetVersion: unsafe extern "C" fn() -> *const c_char;
    fmi2SetDebugLogging: unsafe extern "C" fn(Comp, c_int, usize, *const *const c_char) -> c_int;
    fmi2Instantiate: unsafe extern "C" fn(*const c_char, c_int, *const c_char, *const c_char, *const Callbacks, c_int, c_int) -> Comp;
    fmi2FreeInstance: unsafe extern "C" fn(Comp);
    fmi2SetupExperiment: unsafe extern "C" fn(Comp, c_int, f64, f64, c_int, f64) -> c_int;
    fmi2EnterInitializationMode: unsafe extern "C" fn(Comp) -> c_int;
    fmi2ExitInitializationMode: unsafe extern "C" fn(Comp) -> c_int;
    fmi2Terminate: unsafe extern "C" fn(Comp) -> c_int;
    fmi2Reset: unsafe extern "C" fn(Comp) -> c_int;
    fmi2GetReal: unsafe extern "C" fn(Comp, *const u32, usize, *mut f64) -> c_int;
    fmi2GetInteger: unsafe extern "C" fn(Comp, *const u32, usize, *mut c_int) -> c_int;
    fmi2GetBoolean: unsafe extern "C" fn(Comp, *const u32, usize, *mut c_int) -> c_int;
    fmi2GetString: unsafe extern "C" fn(Comp, *const u32, usize, *mut *const c_char) -> c_int;
    fmi2SetReal: unsafe extern "C" fn(Comp, *const u32, usize, *const f64) -> c_int;
    fmi2SetInteger: unsafe extern "C" fn(Comp, *const u32, usize, *const c_int) -> c_int;
    fmi2SetBoolean: unsafe extern "C" fn(Comp, *const u32, usize, *const c_int) -> c_int;
    fmi2SetString: unsafe extern "C" fn(Comp, *const u32, usize, *const *const c_char) -> c_int;
    fmi2GetFMUstate: unsafe extern "C" fn(Comp, *mut *mut c_void) -> c_int;
    fmi2SetFMUstate: unsafe extern "C" fn(Comp, *mut c_void) -> c_int;
    fmi2FreeFMUstate: unsafe extern "C" fn(Comp, *mut *mut c_void) -> c_int;
    fmi2SerializedFMUstateSize: unsafe extern "C" fn(Comp, *mut c_void, *mut usize) -> c_int;
    fmi2SerializeFMUstate: unsafe extern "C" fn(Comp, *mut c_void, *mut u8, usize) -> c_int;
    fmi2DeSerializeFMUstate: unsafe extern "C" fn(Comp, *const u8, usize, *mut *mut c_void) -> c_int;
    fmi2GetDirectionalDerivative: unsafe extern "C" fn(Comp, *const u32, usize, *const u32, usize, *const f64, *mut f64) -> c_int;
    fmi2SetRealInputDerivatives: unsafe extern "C" fn(Comp, *const u32, usize, *const c_int, *const f64) -> c_int;
    fmi2GetRealOutputDerivatives: unsafe extern "C" fn(Comp, *const u32, usize, *const c_int, *mut f64) -> c_int;
    fmi2DoStep: unsafe extern "C" fn(Comp, f64, f64, c_int) -> c_int;
    fmi2CancelStep: unsafe extern "C" fn(Comp) -> c_int;
    fmi2GetStatus: unsafe extern "C" fn(Comp, c_int, *mut c_int) -> c_int;
    fmi2GetRealStatus: unsafe extern "C" fn(Comp, c_int, *mut f64) -> c_int;
    fmi2GetIntegerStatus: unsafe extern "C" fn(Comp, c_int, *mut c_int) -> c_int;
    fmi2GetBooleanStatus: unsafe extern "C" fn(Comp, c_int, *mut c_int) -> c_int;
    fmi2GetStringStatus: unsafe extern "C" fn(Comp, c_int, *mut *const c_char) -> c_int;
}
