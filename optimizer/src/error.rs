//! [`OptimizerError`]: why an optimization could not be set up or run.

use entrynav::beacons::BeaconError;
use entrynav::observability::ObservabilityError;
use entrynav::scenario::ScenarioError;
use thiserror::Error;

/// Why an optimization could not be set up or run.
#[derive(Debug, Error)]
pub enum OptimizerError {
    /// The request has no feasible answer (no site visible for the whole entry, k larger than
    /// the number of candidates, an orbit below the surface, …).
    #[error("infeasible request: {0}")]
    Infeasible(String),
    /// An argument is out of range or inputs do not fit together.
    #[error("invalid input: {0}")]
    InvalidInput(String),
    /// The observability analysis failed.
    #[error(transparent)]
    Observability(#[from] ObservabilityError),
    /// The scenario could not be built or validated.
    #[error(transparent)]
    Scenario(#[from] ScenarioError),
    /// A beacon could not be built.
    #[error(transparent)]
    Beacon(#[from] BeaconError),
    /// The nominal position bound could not be formed.
    #[error(transparent)]
    NominalBound(#[from] entrynav::sim::bounds::NominalBoundError),
    /// argmin failed while running `what` (the particle swarm or a Nelder–Mead polish).
    #[error("solver failure: {what}")]
    Argmin {
        /// The argmin solver that failed.
        what: &'static str,
        /// argmin's error.
        #[source]
        source: argmin::core::Error,
    },
    /// An argmin run ended without any best point (it evaluated nothing).
    #[error("solver failure: {what} found no point")]
    NoPoint {
        /// The argmin solver or search that found nothing.
        what: &'static str,
    },
    /// clarabel refused the data or settings of `what` before solving.
    #[error("solver failure: clarabel setup of {what}")]
    ClarabelSetup {
        /// The conic program being set up.
        what: &'static str,
        /// clarabel's error.
        #[source]
        source: clarabel::solver::SolverError,
    },
    /// clarabel ran but ended without a (reduced-accuracy) solution of `what`.
    #[error("solver failure: clarabel did not solve {what}: {status:?}")]
    Unsolved {
        /// The conic program that was not solved.
        what: &'static str,
        /// How clarabel stopped (neither `Solved` nor `AlmostSolved`).
        status: clarabel::solver::SolverStatus,
    },
    /// The Monte Carlo behind an objective failed: the truth run of the PCRLB objective, or the
    /// filters of a tuning evaluation.
    #[error(transparent)]
    Trade(#[from] entrynav::sim::TradeError),
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::error::Error as _;

    /// The text `entrynav` prints for an error: the message, then every source (`{:#}` of
    /// anyhow).
    fn chain(e: &OptimizerError) -> String {
        let mut text = e.to_string();
        let mut source = e.source();
        while let Some(s) = source {
            text += &format!(": {s}");
            source = s.source();
        }
        text
    }

    #[test]
    fn solver_errors_keep_their_typed_source() {
        let argmin = argmin::core::Error::msg("simplex collapsed");
        let e = OptimizerError::Argmin {
            what: "Nelder-Mead",
            source: argmin,
        };
        assert_eq!(chain(&e), "solver failure: Nelder-Mead: simplex collapsed");
        let e = OptimizerError::ClarabelSetup {
            what: "the relaxation",
            source: clarabel::solver::SolverError::BadInputData("A has the wrong shape"),
        };
        assert!(matches!(
            e.source()
                .and_then(|s| s.downcast_ref::<clarabel::solver::SolverError>()),
            Some(clarabel::solver::SolverError::BadInputData(_))
        ));
        assert_eq!(
            chain(&e),
            "solver failure: clarabel setup of the relaxation: Bad input data: A has the wrong shape"
        );
        let e = OptimizerError::Unsolved {
            what: "the relaxation",
            status: clarabel::solver::SolverStatus::InsufficientProgress,
        };
        assert_eq!(
            e.to_string(),
            "solver failure: clarabel did not solve the relaxation: InsufficientProgress"
        );
    }
}
