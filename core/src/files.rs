//! How the I/O-free core asks its caller for the text of a file a scenario refers to (tabulated
//! atmospheres): the caller passes a [`FileLoader`] and decides where files come from (the CLI
//! reads the disk relative to the scenario file, the FMU only its `resources/` folder).

use thiserror::Error;

/// A file the caller's loader could not provide.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
#[error("cannot read {path}: {reason}")]
pub struct FileError {
    /// The file as the loader resolved it (or as written, if it could not be resolved).
    pub path: String,
    /// Why it could not be read.
    pub reason: String,
}

impl FileError {
    /// A `FileError` for `path` with `reason`.
    pub fn new(path: impl Into<String>, reason: impl Into<String>) -> Self {
        FileError {
            path: path.into(),
            reason: reason.into(),
        }
    }
}

/// The caller's file loader: the text of the file named `path` (as written in the scenario).
pub type FileLoader<'a> = dyn Fn(&str) -> Result<String, FileError> + 'a;

/// A loader that provides no file at all (built-in scenarios refer to none).
pub fn no_files(path: &str) -> Result<String, FileError> {
    Err(FileError::new(path, "no file access here"))
}
