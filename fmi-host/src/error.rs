//! [`HostError`]: why the host could not open, load or drive an FMU.

use crate::instance::Message;
use entrynav_fmu::instance::Status;
use entrynav_fmu_archive::ArchiveError;
use std::ffi::NulError;
use thiserror::Error;

/// Why the host could not open, load or drive an FMU.
#[derive(Debug, Error)]
pub enum HostError {
    /// The archive cannot be opened, or is not what this build packs.
    #[error(transparent)]
    Archive(#[from] ArchiveError),
    /// The shared library cannot be loaded.
    #[error("cannot load {path}: {source}")]
    Load {
        /// The library.
        path: String,
        /// The loader's error.
        source: libloading::Error,
    },
    /// The shared library lacks an FMI function.
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
    Instantiate(Vec<Message>),
    /// An FMI call returned a status other than OK.
    #[error("{call} returned {status:?}: {messages:?}")]
    Call {
        /// The call.
        call: &'static str,
        /// The statuses returned.
        status: Vec<i32>,
        /// The instance's log.
        messages: Vec<Message>,
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
