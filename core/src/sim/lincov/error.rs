//! [`EntryLinCovError`]: why a LinCov cannot be formed.

use crate::sim::engine::SimError;
use crate::state_dim::UnsupportedDimension;
use thiserror::Error;

/// Why a LinCov cannot be formed.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum EntryLinCovError {
    /// The filter's gain is not a function of its own covariance along the nominal.
    #[error(
        "LinCov cannot analyse filter '{filter}': {reason}; supported filters: ekf, ukf, ci, dcifaif"
    )]
    UnsupportedFilter {
        /// Filter name.
        filter: String,
        /// Why.
        reason: String,
    },
    /// Something in the scenario LinCov cannot linearise.
    #[error("LinCov cannot analyse scenario '{scenario}': {field} = {value} ({reason})")]
    UnsupportedScenario {
        /// Scenario name.
        scenario: String,
        /// The configuration field.
        field: String,
        /// Its value.
        value: String,
        /// Why.
        reason: String,
    },
    /// The nominal truth failed.
    #[error("the nominal truth failed: {0}")]
    Truth(#[from] SimError),
    /// The nominal run has no measurement epoch.
    #[error("the nominal run of scenario '{0}' has no measurement epoch")]
    NoEpochs(String),
    /// A ±h run has a different epoch schedule (a sensor period that changed).
    #[error("the run with parameter {parameter} perturbed has no epoch at t = {t} s")]
    Schedule {
        /// Parameter.
        parameter: String,
        /// Epoch \[s\].
        t: f64,
    },
    /// A value became non-finite.
    #[error("{what} became non-finite at t = {t} s")]
    NonFinite {
        /// What.
        what: String,
        /// Epoch \[s\].
        t: f64,
    },
    /// The filter could not be built or its covariance failed.
    #[error("the filter failed along the nominal: {0}")]
    Filter(String),
    /// The second-order terms could not be differenced (`LinCovOptions::second_order_mean`).
    #[error(
        "the second-order mean at t = {t} s: the filter's model fails {step:.3e} from the nominal \
         in state {state} ({reason}): the deviations are too large for a second-order expansion \
         (a Monte Carlo of this filter is likely to diverge); run without --second-order-mean"
    )]
    SecondOrder {
        /// Epoch \[s\].
        t: f64,
        /// Name of the state differenced.
        state: String,
        /// Its step.
        step: f64,
        /// What failed.
        reason: String,
    },
    /// The filter dimension is not supported.
    #[error(transparent)]
    Dimension(#[from] UnsupportedDimension),
}
