//! Relay orbiters on circular orbits (seed 002 §4.2, eq. 55–62).
//!
//! **Unknowns.** Per orbiter the longitude of the ascending node Ω, the inclination i and the
//! initial argument of latitude f of a circular orbit of radius `ρ = R + a` at the common altitude
//! `a` (eq. 55–56). Two-body motion on a circle is uniform: with `n = √(μ/ρ³)`,
//! `r_B(t) = ρ [cos(f + nt) P + sin(f + nt) Q]`, `P = (cos Ω, sin Ω, 0)`,
//! `Q = (−sin Ω cos i, cos Ω cos i, sin i)` — exactly what [`entrynav::beacons::Orbiter`]
//! propagates for these elements.
//!
//! **Objective.** With `n_j(t)` the unit vector from orbiter j to the vehicle (eq. 29) and
//! `F(t) = Σ_{j visible} n_j n_jᵀ` the unit-σ range FIM of the vehicle position:
//!
//! * [`OrbiterObjective::DetN3`] (three orbiters, eq. 57 and 62):
//!   `J = ∫ det F dt = ∫ [n₁·(n₂ × n₃)]² dt`, zero at epochs where an orbiter is hidden; at most
//!   1 per second, so at most 240 over the 240 s entry;
//! * [`OrbiterObjective::LogDet`] (any n ≥ 3): `J = ∫ log max(det F, 10⁻⁹) dt`.
//!
//! The integral is the trapezoid rule over the trajectory samples ([`crate::trajectory`]).
//!
//! **Visibility** (eq. 58–60) enters as a finite graded penalty: the search minimises
//! `−J + c ∫ Σ_j max(0, −m_j(t)) dt`, where `m_j` is the visibility margin θ₀ + θ₁ − θ \[rad\] of
//! [`orbiter_visibility_margin`](entrynav::beacons::orbiter_visibility_margin) and `c` = [`OrbiterProblem::penalty_per_rad_s`].
//!
//! Files: `objective.rs` the objective, `problem.rs` the problem and its settings,
//! `solution.rs` what the search gives; `elements.rs` the unknowns of one orbiter;
//! `evaluation.rs` positions, the objective along the trajectory and the search.

mod elements;
mod evaluation;
pub mod objective;
pub mod problem;
pub mod solution;

pub use elements::OrbitElements;
pub use objective::{LOG_DET_FLOOR, OrbiterObjective};
pub use problem::{DEFAULT_PENALTY_PER_RAD_S, OrbiterProblem, default_search};
pub use solution::{OrbiterEvaluation, OrbiterSolution};
