//! What an instance answers and logs: [`Status`] (fmi2Status), where its messages go
//! ([`LogSink`]) and why an instantiation is refused ([`InstantiateError`]).

use thiserror::Error;

/// fmi2Status.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord)]
pub enum Status {
    /// fmi2OK.
    Ok = 0,
    /// fmi2Warning.
    Warning = 1,
    /// fmi2Discard.
    Discard = 2,
    /// fmi2Error.
    Error = 3,
    /// fmi2Fatal.
    Fatal = 4,
}

/// Where log messages go: (status, category, message).
pub type LogSink = Box<dyn Fn(Status, &str, &str) + Send>;

/// Why fmi2Instantiate refuses.
#[derive(Debug, Error)]
pub enum InstantiateError {
    /// An empty instance name.
    #[error("fmi2Instantiate: the instance name is empty")]
    EmptyName,
    /// A GUID that is not the model's.
    #[error("fmi2Instantiate: GUID '{given}' does not match this FMU: {expected}")]
    Guid {
        /// The GUID given.
        given: String,
        /// What this binary accepts (and which model the given GUID belongs to, if any).
        expected: String,
    },
    /// A specific FMU whose embedded scenario cannot be loaded.
    #[error("fmi2Instantiate: the embedded scenario of {identifier} cannot be used: {reason}")]
    Embedded {
        /// The model identifier.
        identifier: String,
        /// Why.
        reason: String,
    },
}
