//! # entrynav-optimizer — beacon and orbiter geometry for Mars entry navigation
//!
//! Seed 002 (Yu, Cui, Xu, Zhu) shows that the geometry of the radio beacons is the main lever on
//! entry navigation. This crate searches for better geometries than the paper's and certifies how
//! close to optimal a selection of ground sites is:
//!
//! * [`orbiters`] — `n` relay orbiters on circular orbits at a given altitude, unknowns
//!   (Ω, i, f) per orbiter (seed 002 eq. 55–56), line of sight by eq. 58–60, objective
//!   `∫ det(N₃) dt` (eq. 57, 62) for three orbiters and `∫ log det(Σ nnᵀ) dt` otherwise;
//! * [`ground`] — latitude/longitude of N surface beacons that are each visible during the whole
//!   entry (eq. 52), maximising the minimum over the trajectory of the degree of observability δ
//!   (eq. 49), the time-integrated log det of the range FIM, or the minimum over time of its
//!   smallest eigenvalue;
//! * [`select`] — choose k of m candidate sites with the convex relaxation of Joshi & Boyd
//!   (IEEE TSP 2009) solved by clarabel: D-optimal (log det through exponential and PSD cones)
//!   or E-optimal (max-min λ_min as an SDP); an upper bound, a rounded and swap-improved
//!   selection, and the certified gap of any selection;
//! * [`free`] — N free unit vectors (no visibility), whose optimum `(N/3)³` (eq. 40) checks the
//!   search;
//! * [`search`] — the global search shared by all of them: seeded multi-start particle swarm
//!   followed by a Nelder–Mead polish (argmin, `Vec<f64>` backend), reproducible from a seed,
//!   with evaluation counts and a progress callback;
//! * [`output`] — scenario files carrying an optimized geometry (accepted by `entrynav trade`);
//! * [`tune`] — the process-noise (and assumed measurement-noise) factors that make a navigation
//!   filter consistent (`entrynav tune`), by Nelder–Mead over a common-random-number Monte Carlo.
//!
//! Constraints are never passed to the solvers as NaN or infinity: visibility is handled by a
//! finite penalty graded by how far (in radians) a beacon is below the horizon, and every cost is
//! made finite before argmin sees it.
//!
//! Units are SI inside (m, s, rad); degrees appear only in [`orbiters::OrbitElements::degrees`],
//! [`ground::Site`] accessors and the scenario files.
#![warn(missing_docs)]

// Links the system OpenBLAS/LAPACK that clarabel's SDP cone calls.
use openblas_src as _;

pub mod free;
pub mod ground;
pub mod lincov_score;
pub mod orbiters;
pub mod orbiters_bound;
pub mod orbiters_lincov;
pub mod orbiters_nav;
pub mod output;
pub mod search;
pub mod select;
pub mod trajectory;
pub mod tune;

pub use ground::{GroundObjective, GroundProblem, GroundSolution, Site};
pub use lincov_score::{LinCovFigure, LinCovFigures, LinCovScore};
pub use orbiters::{OrbitElements, OrbiterObjective, OrbiterProblem, OrbiterSolution};
pub use orbiters_bound::{OrbiterBoundProblem, OrbiterBoundSolution};
pub use orbiters_lincov::OrbiterLinCovSolution;
pub use orbiters_nav::{BoundFigure, OrbiterNavProblem, OrbiterNavSolution};
pub use search::{SearchOptions, SearchResult, minimize, polish_from};
pub use select::{
    AtMost, BranchBoundOptions, BranchBoundReport, ProofStatus, Selection, SelectionCriterion,
    SelectionProblem, SelectionReport,
};
pub use trajectory::Trajectory;

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
    NominalBound(#[from] entrynav::sim::bounds::nominal_bound::NominalBoundError),
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

/// A progress callback: `(evaluations done, evaluations budgeted)`. Called from worker threads.
pub type Progress<'a> = &'a (dyn Fn(usize, usize) + Sync);

/// A progress callback that does nothing.
pub fn no_progress(_done: usize, _total: usize) {}

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
