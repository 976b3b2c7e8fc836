//! [`EngineError`]: why an engine step or set-up failed.

use super::filter::BuildError;
use super::truth::SimError;
use crate::estimation::nav::NavError;
use thiserror::Error;

/// Why an engine step or set-up failed.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum EngineError {
    /// The filter does not fit the scenario.
    #[error(transparent)]
    Nav(#[from] NavError),
    /// The filter could not be built.
    #[error(transparent)]
    Build(#[from] BuildError),
    /// The truth became non-finite.
    #[error(transparent)]
    Truth(#[from] SimError),
    /// A step that does not start where the previous one ended.
    #[error("step starts at t = {got} s but the current communication point is t = {expected} s")]
    CommunicationPoint {
        /// Current time of the engine \[s\].
        expected: f64,
        /// Start time asked for \[s\].
        got: f64,
    },
    /// A step size that is not finite and positive.
    #[error("communication step size must be finite and > 0 (got {0})")]
    StepSize(f64),
    /// A non-finite input.
    #[error("input '{0}' is not finite")]
    NonFiniteInput(&'static str),
}
