//! Our FMI 2.0 host: unpacks one of our `.fmu` files, loads its shared library with libloading
//! and calls the fmi2 functions through a safe [`Slave`] wrapper. `entrynav fmu check` compares
//! it with the in-process [`Instance`](entrynav_fmu::instance::Instance) bit for bit;
//! `entrynav fmu fuzz` drives random call sequences through it.
//!
//! It is a crate of its own so that the FMU library (`entrynav-fmu`, the cdylib shipped in every
//! `.fmu`) carries only the FMU: the host's libloading and zip stay in the `entrynav` command.
//!
//! Modules: [`api`] (the fmi2 functions of a loaded library and the logger the host passes),
//! [`api3`] (the fmi3 functions of a loaded library and the FMI 3.0 log callback the host passes),
//! [`unpack`](mod@unpack) (opening an archive, reading its model description, loading its library) and
//! `slave` (one instance through the host, and reading all outputs of it or of an in-process
//! instance the same way).
#![warn(missing_docs)]

pub mod api;
pub mod api3;
mod slave;
pub mod unpack;

pub use api::{Api, Callbacks, Comp, HostLogger};
pub use api3::{Api3, Inst3, Log3, Logger3, Message3, State3, host_logger3};
pub use slave::{OutputGroups, Slave, file_uri, in_process_get_all, output_groups};
pub use unpack::{Unpacked, unpack};

use entrynav_fmu::binding::BindingError;
use entrynav_fmu::instance::{InstantiateError, Status};
use std::ffi::NulError;
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
    /// Not a zip archive, an entry missing from it, or an archive that cannot be extracted.
    #[error("{path}: {what}: {source}")]
    Archive {
        /// The `.fmu` file.
        path: String,
        /// What was being done.
        what: &'static str,
        /// The zip reader's error.
        source: zip::result::ZipError,
    },
    /// The model description is not well-formed XML.
    #[error("{path}: modelDescription.xml: {source}")]
    Xml {
        /// The `.fmu` file.
        path: String,
        /// The XML reader's error.
        source: quick_xml::Error,
    },
    /// The model description names no usable model identifier (one of letters, digits and `_`).
    #[error("{path}: no usable modelIdentifier in modelDescription.xml")]
    ModelIdentifier {
        /// The `.fmu` file.
        path: String,
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
    /// The shared library cannot be loaded.
    #[error("cannot load {path}: {source}")]
    Load {
        /// The library.
        path: String,
        /// The loader's error.
        source: libloading::Error,
    },
    /// The shared library lacks an fmi2 function.
    #[error("cannot load {path}: no symbol {symbol}: {source}")]
    Symbol {
        /// The library.
        path: String,
        /// The function.
        symbol: &'static str,
        /// The loader's error.
        source: libloading::Error,
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

/// The host's results.
pub(crate) type Result<T> = std::result::Result<T, HostError>;
