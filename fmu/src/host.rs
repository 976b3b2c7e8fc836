//! Our FMI 2.0 host: unpacks a `.fmu`, loads its shared library with libloading and calls the
//! fmi2 functions through a safe [`Slave`] wrapper. `entrynav fmu check` compares it with the
//! in-process [`Instance`] bit for bit; `entrynav fmu fuzz` drives random call sequences through
//! it.
//!
//! The logger is declared without the C varargs (stable Rust cannot define variadic functions);
//! on x86-64 System V a variadic call to it is ABI-compatible, and our FMUs never pass format
//! arguments (messages are pre-formatted, `%` escaped as `%%`).

#![allow(non_snake_case)]

use crate::instance::{Instance, Status};
use crate::vars::{Causality, Model, Type, Value, Var};
use crate::xml::model_description;
use entrynav::scenario::BUILTIN_NAMES;
use std::ffi::{CStr, CString, NulError, c_char, c_int, c_void};
use std::io::Read;
use std::path::{Path, PathBuf};
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
        "modelDescription.xml is not what this build's variable table generates (stale FMU or drifted table)"
    )]
    StaleModelDescription,
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

extern "C" fn host_logger(
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
    /// Which of our models it is.
    pub model: Model,
    /// Its fmi2 functions.
    pub api: Api,
}

impl Drop for Unpacked {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.dir);
    }
}

/// Unpack `file` into a fresh temporary folder and load its library; the FMU must be one of ours
/// with the model description this build generates and every built-in scenario in `resources/`.
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
    let model = Model::ALL
        .into_iter()
        .find(|m| model_description(*m) == xml)
        .ok_or(HostError::StaleModelDescription)?;
    let dir = std::env::temp_dir().join(format!(
        "entrynav fmu check {} {}",
        std::process::id(),
        model.identifier()
    ));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).map_err(io("cannot create", &dir))?;
    zip.extract(&dir)
        .map_err(|e| archive(format!("cannot extract to {}: {e}", dir.display())))?;
    let so = dir
        .join("binaries/linux64")
        .join(format!("{}.so", model.identifier()));
    if !so.exists() {
        return Err(HostError::MissingFile(format!(
            "binaries/linux64/{}.so",
            model.identifier()
        )));
    }
    for name in BUILTIN_NAMES {
        if !dir.join(format!("resources/{name}.toml")).exists() {
            return Err(HostError::MissingFile(format!("resources/{name}.toml")));
        }
    }
    let api = Api::load(&so)?;
    Ok(Unpacked { dir, model, api })
}

/// One instance through the host.
pub struct Slave<'a> {
    /// The library's functions.
    pub api: &'a Api,
    /// The instance.
    pub c: Comp,
    /// Messages the instance logged: (status, text).
    pub log: Box<Mutex<Vec<(i32, String)>>>,
    _callbacks: Box<Callbacks>,
}

impl<'a> Slave<'a> {
    /// Instantiate `u`'s model as co-simulation slave `name` with `guid` and the resource URI
    /// `resources`, logging on.
    pub fn new(u: &'a Unpacked, name: &str, guid: &str, resources: &str) -> Result<Slave<'a>> {
        let log: Box<Mutex<Vec<(i32, String)>>> = Box::new(Mutex::new(Vec::new()));
        let callbacks = Box::new(Callbacks {
            logger: Some(host_logger),
            allocate: None,
            free: None,
            step_finished: None,
            env: &*log as *const _ as *mut c_void,
        });
        let (n, g, r) = (
            CString::new(name)?,
            CString::new(guid)?,
            CString::new(resources)?,
        );
        // SAFETY: valid C strings and callbacks that outlive the instance.
        let c = unsafe {
            (u.api.fmi2Instantiate)(n.as_ptr(), 1, g.as_ptr(), r.as_ptr(), &*callbacks, 0, 0)
        };
        let s = Slave {
            api: &u.api,
            c,
            log,
            _callbacks: callbacks,
        };
        if c.is_null() {
            return Err(HostError::Instantiate(s.messages()));
        }
        Ok(s)
    }

    /// The messages logged so far.
    pub fn messages(&self) -> Vec<(i32, String)> {
        self.log.lock().map(|l| l.clone()).unwrap_or_default()
    }

    /// Set one variable; returns the fmi2Status.
    pub fn set(&self, v: &Var, val: &Value) -> i32 {
        let vr = [v.vr];
        // SAFETY: one reference and one value of the right type.
        unsafe {
            match val {
                Value::Real(x) => (self.api.fmi2SetReal)(self.c, vr.as_ptr(), 1, x),
                Value::Integer(x) => (self.api.fmi2SetInteger)(self.c, vr.as_ptr(), 1, x),
                Value::Boolean(x) => {
                    (self.api.fmi2SetBoolean)(self.c, vr.as_ptr(), 1, &(*x as c_int))
                }
                Value::String(s) => {
                    let cs = CString::new(s.as_str()).unwrap_or_default();
                    (self.api.fmi2SetString)(self.c, vr.as_ptr(), 1, &cs.as_ptr())
                }
            }
        }
    }

    /// All values of `vars` (one call per type), as f64 bit patterns / integers.
    pub fn get_all(&self, groups: &OutputGroups) -> Result<Vec<u64>> {
        let mut out = Vec::new();
        let mut r = vec![0.0; groups.real.len()];
        let mut i = vec![0; groups.int.len()];
        let mut b = vec![0; groups.bool.len()];
        // SAFETY: buffers sized to the reference lists.
        let st = unsafe {
            [
                (self.api.fmi2GetReal)(self.c, groups.real.as_ptr(), r.len(), r.as_mut_ptr()),
                (self.api.fmi2GetInteger)(self.c, groups.int.as_ptr(), i.len(), i.as_mut_ptr()),
                (self.api.fmi2GetBoolean)(self.c, groups.bool.as_ptr(), b.len(), b.as_mut_ptr()),
            ]
        };
        if st != [0, 0, 0] {
            return Err(HostError::Call {
                call: "fmi2Get*",
                status: st.to_vec(),
                messages: self.messages(),
            });
        }
        out.extend(r.iter().map(|x| x.to_bits()));
        out.extend(i.iter().map(|x| *x as u64));
        out.extend(b.iter().map(|x| (*x != 0) as u64));
        Ok(out)
    }
}

impl Drop for Slave<'_> {
    fn drop(&mut self) {
        // SAFETY: our instance (or null).
        unsafe { (self.api.fmi2FreeInstance)(self.c) };
    }
}

/// The output value references of a model, by type.
pub struct OutputGroups {
    /// Real outputs.
    pub real: Vec<u32>,
    /// Integer outputs.
    pub int: Vec<u32>,
    /// Boolean outputs.
    pub bool: Vec<u32>,
}

/// The output references of `vars`, grouped by type.
pub fn output_groups(vars: &[Var]) -> OutputGroups {
    let pick = |t: Type| {
        vars.iter()
            .filter(|v| v.causality == Causality::Output && v.ty == t)
            .map(|v| v.vr)
            .collect()
    };
    OutputGroups {
        real: pick(Type::Real),
        int: pick(Type::Integer),
        bool: pick(Type::Boolean),
    }
}

/// [`Slave::get_all`] on an in-process instance.
pub fn in_process_get_all(inst: &mut Instance, g: &OutputGroups) -> Result<Vec<u64>> {
    let mut out = Vec::new();
    for (t, vrs) in [
        (Type::Real, &g.real),
        (Type::Integer, &g.int),
        (Type::Boolean, &g.bool),
    ] {
        let vals = inst
            .get("fmi2Get", t, vrs)
            .map_err(|status| HostError::InProcess {
                call: "fmi2Get",
                status,
            })?;
        out.extend(vals.into_iter().map(|v| match v {
            Value::Real(x) => x.to_bits(),
            Value::Integer(x) => x as u64,
            Value::Boolean(x) => x as u64,
            Value::String(_) => 0,
        }));
    }
    Ok(out)
}

/// The `file://` URI of a folder, percent-encoded.
pub fn file_uri(dir: &Path) -> String {
    let mut s = String::from("file://");
    for b in dir.to_string_lossy().bytes() {
        match b {
            b'A'..=b'Z' | b'a'..=b'z' | b'0'..=b'9' | b'/' | b'-' | b'_' | b'.' | b'~' => {
                s.push(b as char)
            }
            _ => s.push_str(&format!("%{b:02X}")),
        }
    }
    s
}
