//! What writing a `.fmu` or `.ssp` archive can fail on, kept apart until the archive's path can
//! name it.

use crate::error::StudyError;

/// A failure while writing an archive: the archive's own, or one the study layer names.
pub enum ZipOrStudy {
    /// The archive library's (or the file system's, through it).
    Zip(zip::result::ZipError),
    /// One the study layer names.
    Study(Box<StudyError>),
}

impl From<zip::result::ZipError> for ZipOrStudy {
    fn from(e: zip::result::ZipError) -> Self {
        ZipOrStudy::Zip(e)
    }
}

impl From<std::io::Error> for ZipOrStudy {
    fn from(e: std::io::Error) -> Self {
        ZipOrStudy::Zip(e.into())
    }
}

impl From<StudyError> for ZipOrStudy {
    fn from(e: StudyError) -> Self {
        ZipOrStudy::Study(Box::new(e))
    }
}

impl From<crate::output::OutputError> for ZipOrStudy {
    fn from(e: crate::output::OutputError) -> Self {
        ZipOrStudy::Study(Box::new(e.into()))
    }
}

impl ZipOrStudy {
    /// The study error of a failure while writing `path`.
    pub fn at(self, path: &std::path::Path) -> StudyError {
        match self {
            ZipOrStudy::Study(e) => *e,
            ZipOrStudy::Zip(e) => StudyError::Failed(format!("writing {}: {e}", path.display())),
        }
    }
}
