//! What a study returns when it does not finish: one error type for the whole layer, and its
//! [`ErrorKind`], which each front end maps once (the command line to its exit code, Python to
//! an exception class).

use crate::options::OptionError;
use crate::output::atomic_file::OutputError;
use entrynav::sim::{SimError, TradeError};
use entrynav_loader::LoadError;

/// Why a study stopped.
#[derive(Debug, thiserror::Error)]
pub enum StudyError {
    /// An option outside its range (refused before any work).
    #[error(transparent)]
    Option(#[from] OptionError),
    /// The scenario does not load or validate (refused before any work).
    #[error(transparent)]
    Scenario(Box<LoadError>),
    /// The scenario's configuration is invalid (refused before any work).
    #[error(transparent)]
    Config(Box<entrynav::scenario::ScenarioError>),
    /// Anything else refused before the work starts: a combination of options, an input file
    /// that is not what it should be.
    #[error("{0}")]
    Refused(String),
    /// A failure while doing the work.
    #[error("{0}")]
    Failed(String),
    /// An output could not be written (the work itself is done).
    #[error(transparent)]
    Output(Box<OutputError>),
    /// The Monte Carlo engine.
    #[error(transparent)]
    Trade(Box<TradeError>),
    /// A truth simulation.
    #[error(transparent)]
    Sim(Box<SimError>),
    /// Stopped by the caller (Ctrl-C): what was finished is kept where the study supports it.
    #[error("interrupted: {0}")]
    Interrupted(String),
}

/// The errors of the libraries below, boxed: a `StudyError` stays a few words wide however large
/// the error it carries.
macro_rules! boxed_from {
    ($($variant:ident($source:ty)),*) => {$(
        impl From<$source> for StudyError {
            fn from(e: $source) -> Self {
                StudyError::$variant(Box::new(e))
            }
        }
    )*};
}

boxed_from!(
    Scenario(LoadError),
    Config(entrynav::scenario::ScenarioError),
    Output(OutputError),
    Trade(TradeError),
    Sim(SimError)
);

/// The three ways a study ends without its result.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ErrorKind {
    /// Refused before any work: a bad option, scenario, input or output path.
    Refused,
    /// Failed during the work, or while writing its result.
    Failed,
    /// Stopped by the caller.
    Interrupted,
}

impl StudyError {
    /// Which of the three ways this is.
    pub fn kind(&self) -> ErrorKind {
        match self {
            StudyError::Option(_)
            | StudyError::Scenario(_)
            | StudyError::Config(_)
            | StudyError::Refused(_) => ErrorKind::Refused,
            StudyError::Trade(e) if matches!(**e, TradeError::Truth(_)) => ErrorKind::Failed,
            StudyError::Trade(_) => ErrorKind::Refused,
            StudyError::Failed(_) | StudyError::Output(_) | StudyError::Sim(_) => ErrorKind::Failed,
            StudyError::Interrupted(_) => ErrorKind::Interrupted,
        }
    }

    /// `context: self`, keeping the kind (what `anyhow`'s context adds, for a library).
    pub fn context(self, context: impl std::fmt::Display) -> StudyError {
        let text = format!("{context}: {self}");
        match self.kind() {
            ErrorKind::Refused => StudyError::Refused(text),
            ErrorKind::Failed => StudyError::Failed(text),
            ErrorKind::Interrupted => StudyError::Interrupted(text),
        }
    }
}

/// `e` and its causes, `: `-separated (as `anyhow` prints an error with `{:#}`).
pub fn chain(e: &dyn std::error::Error) -> String {
    let mut text = e.to_string();
    let mut cause = e.source();
    while let Some(c) = cause {
        text.push_str(": ");
        text.push_str(&c.to_string());
        cause = c.source();
    }
    text
}

/// A study's result.
pub type StudyResult<T> = Result<T, StudyError>;
