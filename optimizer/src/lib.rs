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
//! * [`free_vectors`] — N free unit vectors (no visibility), whose optimum `(N/3)³` (eq. 40) checks the
//!   search;
//! * [`search`] — the global search shared by all of them: seeded multi-start particle swarm
//!   followed by a Nelder–Mead polish (argmin, `Vec<f64>` backend), reproducible from a seed,
//!   with evaluation counts and a progress callback;
//! * [`output`] — scenario files carrying an optimized geometry (accepted by `entrynav trade`).
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

pub mod error;
pub mod free_vectors;
pub mod ground;
pub mod lincov_score;
pub mod orbiters;
pub mod orbiters_bound;
pub mod orbiters_lincov;
pub mod orbiters_nav;
pub mod output;
pub mod progress;
pub mod search;
pub mod search_options;
pub mod select;
pub mod trajectory;

pub use error::OptimizerError;
pub use ground::{GroundObjective, GroundProblem, GroundSolution, Site};
pub use lincov_score::{LinCovFigure, LinCovFigures, LinCovScore};
pub use orbiters::{OrbitElements, OrbiterObjective, OrbiterProblem, OrbiterSolution};
pub use orbiters_bound::{OrbiterBoundProblem, OrbiterBoundSolution};
pub use orbiters_lincov::OrbiterLinCovSolution;
pub use orbiters_nav::{BoundFigure, OrbiterNavProblem, OrbiterNavSolution};
pub use progress::{Progress, no_progress};
pub use search::{minimize, polish_from};
pub use search_options::{SearchOptions, SearchResult};
pub use select::{
    AtMost, BranchBoundOptions, BranchBoundReport, ProofStatus, Selection, SelectionCriterion,
    SelectionProblem, SelectionReport,
};
pub use trajectory::Trajectory;
