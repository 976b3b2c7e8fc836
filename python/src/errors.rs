//! Study errors as Python exceptions: a refused option, scenario or input is `ValueError` (a
//! missing scenario file `FileNotFoundError`), a failure during the work `RuntimeError`, Ctrl-C
//! `KeyboardInterrupt` — the same split as the command line's exit codes 2, 1 and 130.

use entrynav_loader::LoadError;
use entrynav_studies::{ErrorKind, StudyError};
use pyo3::PyErr;
use pyo3::exceptions::{PyFileNotFoundError, PyKeyboardInterrupt, PyRuntimeError, PyValueError};

/// A study's error as the Python exception of its kind.
pub fn study_err(e: StudyError) -> PyErr {
    if let StudyError::Scenario(load) = &e
        && matches!(**load, LoadError::NotFound { .. })
    {
        return PyFileNotFoundError::new_err(e.to_string());
    }
    match e.kind() {
        ErrorKind::Refused => PyValueError::new_err(e.to_string()),
        ErrorKind::Failed => PyRuntimeError::new_err(e.to_string()),
        ErrorKind::Interrupted => PyKeyboardInterrupt::new_err(e.to_string()),
    }
}

/// A scenario that does not load.
pub fn load_err(e: LoadError) -> PyErr {
    study_err(e.into())
}

/// A JSON document that does not serialise (a bug, not the user's).
pub fn json_err(e: serde_json::Error) -> PyErr {
    PyRuntimeError::new_err(format!("internal error: {e}"))
}
