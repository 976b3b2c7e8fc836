//! Choose k of m candidate sites: the convex relaxation of Joshi & Boyd ("Sensor selection via
//! convex optimization", IEEE TSP 57(2), 2009), solved by clarabel, with rounding, a swap local
//! search and certified gaps.
//!
//! **Data.** Each candidate i has one or more 3×3 positive semidefinite information blocks
//! `A_i^e` (e = epochs). For the D-optimal criterion the blocks are summed into one matrix per
//! candidate; for the E-optimal one every epoch counts separately.
//!
//! **Problems** (Boolean `z_i ∈ {0, 1}`, `Σ z_i = k`, relaxed to `0 ≤ z_i ≤ 1`):
//!
//! * [`SelectionCriterion::LogDet`] — `max log det Σ_i z_i A_i`. Conic form: with a lower
//!   triangular `L` (diagonal d) and `u ∈ R³`,
//!   `[[Σ z_i A_i, L], [Lᵀ, Diag(d)]] ⪰ 0` (one 6×6 PSD cone) and `(u_j, 1, d_j) ∈ K_exp`
//!   (`e^{u_j} ≤ d_j`, three exponential cones); maximise `Σ u_j`. The PSD condition is
//!   `Σ z A ⪰ L Diag(d)⁻¹ Lᵀ`, whose determinant is `Π d_j`, and the Cholesky factor makes it tight,
//!   so the optimum is `log det Σ z A`.
//! * [`SelectionCriterion::MinEig`] — `max t` subject to `Σ_i z_i A_i^e − t I ⪰ 0` for every
//!   epoch e (one 3×3 PSD cone each): the E-optimal, max-min λ_min design as an SDP.
//!
//! The relaxation's optimum is an **upper bound** on every k-subset's value. The bound reported is
//! the larger of the solver's primal and dual objectives (the dual objective is the certificate),
//! so `gap = bound − value(S)` bounds how far any selection S is from the best k-subset.
//!
//! **Rounding.** The k largest `z_i`, then a swap local search (exchange a chosen and an unchosen
//! site while the value improves). The greedy selection, also swap-improved, is a second start;
//! the better local optimum is the answer ([`heuristics`]).
//!
//! **Side constraints.** [`AtMost`] rows `Σ_{i∈G} z_i ≤ u` (e.g. a minimum spacing between
//! sites: `z_i + z_j ≤ 1` for every close pair, [`separation_constraints`]) enter the relaxation
//! as linear constraints; every heuristic and the enumeration keep to them.
//!
//! **Exact answer.** [`branch_bound`] proves which k-subset is optimal (or certifies a gap) by
//! branch and bound on `z_i ∈ {0, 1}` over the node relaxations, with the cheaper dual bounds of
//! [`bounds`] tried first.
//!
//! | file | role |
//! |---|---|
//! | [`problem`], [`criterion`], [`report`] | the problem, its values and side constraints; the criterion; what a selection gives |
//! | [`heuristics`] | rounding, swap, greedy, brute force, [`SelectionProblem::solve`] |
//! | `relaxation.rs` | the clarabel conic program of a (node) relaxation |
//! | [`bounds`] | valid upper bounds from dual points (Lagrangian duality) |
//! | `node.rs` | one branch-and-bound node: bound, incumbent, branching variable |
//! | [`branch_bound`] | the search: the round loop |
//! | [`branch_bound_report`] | its options, progress, report and proof status |
//! | `search_tree.rs` | the running search: queue, dive, incumbent, batches, counters |
//! | `information.rs` | information blocks of ground sites, spacing constraints |

pub mod bounds;
pub mod branch_bound;
pub mod branch_bound_report;
pub mod criterion;
pub mod dual_point;
pub mod heuristics;
mod information;
mod node;
pub mod problem;
mod relaxation;
pub mod report;
mod search_tree;

pub use branch_bound_report::{
    BranchBoundOptions, BranchBoundProgress, BranchBoundReport, PROOF_GAP, ProofStatus,
};
pub use clarabel::solver::SolverStatus;
pub use criterion::SelectionCriterion;
pub use dual_point::DualPoint;
pub use information::{separation_constraints, site_information};
pub use problem::{AtMost, LN_DET_FLOOR, SelectionProblem};
pub use report::{Relaxation, Selection, SelectionReport};
