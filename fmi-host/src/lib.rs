//! Our FMI 2.0 host: unpacks a `.fmu`, loads its shared library with libloading and calls the
//! fmi2 functions through a safe [`Slave`] wrapper. `entrynav fmu check` compares it with the
//! in-process [`Instance`](crate::instance::Instance) bit for bit; `entrynav fmu fuzz` drives random call sequences through
//! it.
//!
//! The logger is declared without the C varargs (stable Rust cannot define variadic functions);
//! on x86-64 System V a variadic call to it is ABI-compatible, and our FMUs never pass format
//! arguments (messages are pre-formatted, `%` escaped as `%%`).

#![allow(non_snake_case)]

use crate::binding::{Binding, BindingError, read_library};
use crate::instance::{InstantiateError, Status, resolve_spec};
use crate::vars::{Model, ModelSpec};
use crate::xml::description_of;
use entrynav::scenario::BUILTIN_NAMES;
use std::ffi::{CStr, NulError, c_char, c_int, c_void};
use std::io::Read;
use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::Mutex;
use thiserror::Error;

/// Why the host could not unpack, load or drive an FMU.
#[derive(Debug, Error)]
pub enum HostError {
    /// A file could not be opened, read or extracted.
    #[error("{what} {path}: {source}")]
    Io {
        /// What was being done.
        what: &'static str,
        /// The file or folder.
        path: String,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// Not a zip archive, or an entry is missing from it.
    #[error("{path}: {message}")]
    Archive {
        /// The `.fmu` file.
        path: String,
        /// What is wrong.
        message: String,
    },
    /// The archive's model description is not what this build generates.
    #[error(
        "modelDescription.xml is not what this build's variable table generates for {0} (stale FMU or drifted table)"
    )]
    StaleModelDescription(String),
    /// The library's binding cannot be read.
    #[error(transparent)]
    Binding(#[from] BindingError),
    /// The model the library is bound to cannot be rebuilt from the archive.
    #[error(transparent)]
    Model(#[from] InstantiateError),
    /// A file the FMU must contain is missing.
    #[error("the FMU has no {0}")]
    MissingFile(String),
    /// The shared library or one of its symbols cannot be loaded.
    #[error("cannot load {path}: {message}")]
    Load {
        /// The library.
        path: String,
        /// The loader's message.
        message: String,
    },
    /// A string with an interior NUL byte.
    #[error(transparent)]
    Nul(#[from] NulError),
    /// `fmi2Instantiate` returned null.
    #[error("fmi2Instantiate failed: {0:?}")]
    Instantiate(Vec<(i32, String)>),
    /// An fmi2 call returned a status other than OK.
    #[error("{call} returned {status:?}: {messages:?}")]
    Call {
        /// The call.
        call: &'static str,
        /// The statuses returned.
        status: Vec<i32>,
        /// The instance's log.
        messages: Vec<(i32, String)>,
    },
    /// The in-process instance refused a call.
    #[error("in-process {call} failed: {status:?}")]
    InProcess {
        /// The call.
        call: &'static str,
        /// Its status.
        status: Status,
    },
}

type Result<T> = std::result::Result<T, HostError>;

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

pub(super) extern "C" fn host_logger(
    env: *mut c_void,
    _name: *const c_char,
    status: c_int,
    _category: *const c_char,
    msg: *const c_char,
) {
    if env.is_null() || msg.is_null() {
        return;
    }
    // SAFETY: env is the `Mutex<Vec<..>>` the host passed in Callbacks and keeps alive while the
    // instance exists; msg is a C string from the FMU.
    let (log, text) = unsafe {
        (
            &*(env as *const Mutex<Vec<(i32, String)>>),
            CStr::from_ptr(msg).to_string_lossy().replace("%%", "%"),
        )
    };
    if let Ok(mut l) = log.lock() {
        l.push((status, text));
    }
}

macro_rules! api {
    ($($name:ident : $ty:ty;)*) => {
        /// The 34 fmi2 functions of a loaded FMU library.
        #[allow(dead_code, missing_docs)]
        pub struct Api {
            _lib: libloading::Library,
            $(pub $name: $ty,)*
        }

        impl Api {
            fn load(path: &Path) -> Result<Api> {
                // SAFETY: loading the FMU library runs no initialisers with preconditions.
                let lib = unsafe { libloading::Library::new(path) }.map_err(|e| HostError::Load {
                    path: path.display().to_string(),
                    message: e.to_string(),
                })?;
                $(
                    // SAFETY: the symbol has the FMI 2.0 signature.
                    let $name: $ty = *unsafe { lib.get::<$ty>(concat!(stringify!($name), "\0").as_bytes()) }
                        .map_err(|e| HostError::Load {
                            path: path.display().to_string(),
                            message: format!("no symbol {}: {e}", stringify!($name)),
                        })?;
                )*
                Ok(Api { _lib: lib, $($name,)* })
            }
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

/// An unpacked FMU: its folder (removed on drop), model and loaded library.
pub struct Unpacked {
    /// Where it was extracted.
    pub dir: PathBuf,
    /// Which of our models it is (the base model of a specific FMU).
    pub model: Model,
    /// The model with its table and GUID.
    pub spec: Arc<ModelSpec>,
    /// The library's binding (`None`: an unbound development library).
    pub binding: Option<Binding>,
    /// Size of the shared library in bytes.
    pub library_bytes: u64,
    /// Its fmi2 functions.
    pub api: Api,
}

impl Drop for Unpacked {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// The `modelIdentifier` attribute of a model description.
fn model_identifier(xml: &str) -> Option<&str> {
    let rest = &xml[xml.find("modelIdentifier=\"")? + "modelIdentifier=\"".len()..];
    rest.get(..rest.find('"')?)
}

/// Unpack `file` into a fresh temporary folder and load its library; the FMU must be one of ours
/// with the model description this build generates for the model its library is bound to (and,
/// for a generic model, every built-in scenario in `resources/`).
pub fn unpack(file: &Path) -> Result<Unpacked> {
    let io = |what, path: &Path| {
        let path = path.display().to_string();
        move |source| HostError::Io { what, path, source }
    };
    let archive = |message: String| HostError::Archive {
        path: file.display().to_string(),
        message,
    };
    let f = std::fs::File::open(file).map_err(io("cannot open", file))?;
    let mut zip = zip::ZipArchive::new(f).map_err(|e| archive(format!("not a zip: {e}")))?;
    let mut xml = String::new();
    zip.by_name("modelDescription.xml")
        .map_err(|e| archive(format!("no modelDescription.xml: {e}")))?
        .read_to_string(&mut xml)
        .map_err(io("cannot read modelDescription.xml of", file))?;
    let id = model_identifier(&xml)
        .filter(|id| !id.is_empty() && id.chars().all(|c| c.is_ascii_alphanumeric() || c == '_'))
        .ok_or_else(|| archive("no usable modelIdentifier in modelDescription.xml".into()))?
        .to_string();
    let dir = std::env::temp_dir().join(format!(
        "entrynav fmu check {} {id} {}",
        std::process::id(),
        file.file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_default()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).map_err(io("cannot create", &dir))?;
    zip.extract(&dir)
        .map_err(|e| archive(format!("cannot extract to {}: {e}", dir.display())))?;
    let so = dir.join("binaries/linux64").join(format!("{id}.so"));
    let bytes = std::fs::read(&so)
        .map_err(|_| HostError::MissingFile(format!("binaries/linux64/{id}.so")))?;
    let binding = read_library(&bytes)?;
    let spec = match &binding {
        Some(b) => resolve_spec(Some(b), &b.guid, Some(&file_uri(&dir.join("resources"))))?,
        None => Arc::new(ModelSpec::generic(
            Model::from_identifier(&id)
                .ok_or_else(|| HostError::StaleModelDescription(id.clone()))?,
        )),
    };
    if description_of(&spec) != xml {
        return Err(HostError::StaleModelDescription(id));
    }
    if spec.specific().is_none() {
        for name in BUILTIN_NAMES {
            if !dir.join(format!("resources/{name}.toml")).exists() {
                return Err(HostError::MissingFile(format!("resources/{name}.toml")));
            }
        }
    }
    let api = Api::load(&so)?;
    Ok(Unpacked {
        dir,
        model: spec.model(),
        spec,
        binding,
        library_bytes: bytes.len() as u64,
        api,
    })
}

mod slave;

pub use slave::{OutputGroups, Slave, file_uri, in_process_get_all, output_groups};
