//! [`ArchiveError`]: why a `.fmu` cannot be opened as one of ours.

use entrynav_fmu::binding::BindingError;
use entrynav_fmu::instance::InstantiateError;
use thiserror::Error;

/// Why an archive cannot be opened, or is not what this build packs.
#[derive(Debug, Error)]
pub enum ArchiveError {
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
}

/// The results of this crate.
pub(crate) type Result<T> = std::result::Result<T, ArchiveError>;
