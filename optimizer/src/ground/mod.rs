//! Ground beacons visible during the whole entry (seed 002 §4.1, eq. 49–54).
//!
//! **Unknowns.** Latitude and longitude of N surface beacons at a common altitude (0 km: on the
//! reference sphere). They turn with the planet (`r_B(t) = R_z(ωt) r_B,fixed`).
//!
//! **Constraint** (eq. 52): each beacon sees the vehicle above its local horizon at every
//! trajectory sample. The visibility margin of [`ground_visibility_margin`](entrynav::beacons::ground_visibility_margin) is the vehicle's
//! elevation \[rad\] seen from the beacon; a site is feasible when its smallest elevation over the
//! trajectory is at least `min_elevation` (default 0, the paper's rule). The feasible set of one
//! site is an intersection of spherical caps (one per sample), so it is convex on the sphere and
//! lies inside the smallest cap — the one under the end of the trajectory.
//!
//! **Objectives** ([`GroundObjective`]):
//! * `MinDelta` — `max min_t δ(t)` (eq. 49): δ = σ_min/σ_max of the observability matrix of the
//!   scenario's filter model with ranges to the N beacons (method and raw-SI or scaled δ as in
//!   [`entrynav::observability::degree()`]); the search maximises `log10 min_t δ`;
//! * `LogDet` — `∫ log det F(t) dt`, F the range FIM of the vehicle position
//!   `Σ σ⁻² n nᵀ` [m⁻²] (eq. 36); the search maximises the time average;
//! * `MinEig` — `min_t λ_min(F(t))` [m⁻²]; the search maximises its log10;
//! * `PcrlbAvg`, `PcrlbFinal` — the position PCRLB \[m\] along the nominal trajectory
//!   ([`entrynav::sim::bounds::nominal_bound`]: dynamics, prior, every non-radio sensor and the ranges to
//!   the sites together, with the truth's sensors and epochs), averaged over the epochs or at the
//!   last one; the search *minimises* its log10. Unlike the proxies above they bound what
//!   navigation can reach: the time-averaged and the final position RMSE of a trade;
//! * `Navigation` (the default of `entrynav optimize ground`) — both at once, each relative to
//!   the input design: `½ (avg/avg_input + final/final_input)` (1 = as good as the input; see
//!   [`GroundProblem::with_reference`]); minimised. Either bound alone trades the other away
//!   (the final bound alone reached 17.8 m final but 143 m time-averaged on `ground-beacons-3`).
//!
//! **Separation.** Sites closer than a minimum great-circle separation are infeasible
//! ([`GroundProblem::with_min_separation`]): the bound rewards near-duplicate sites whose lines of
//! sight are almost parallel, which a filter's linearisation does not survive (two sites 0.5°
//! apart gave an EKF ANEES/dof of 26).
//!
//! Infeasible sites cost `10⁴ + 10⁴ · Σ_j max(0, min_elevation − elevation_j)` \[rad\]: finite,
//! graded towards the feasible set and worse than every feasible cost.
//!
//! Files: `site.rs` the sites, `objective.rs` the objectives, `problem.rs` the problem and its
//! settings, `solution.rs` what the search gives, `penalty.rs` the cost of infeasible sites;
//! `visibility.rs` eq. 52, the visible grid and the search box; `evaluation.rs` δ(t), the FIM,
//! values, costs and the search; `final_bound.rs` the final PCRLB objective of the orbiter search;
//! `bound_selection.rs`, `lincov_selection.rs`, `lincov_polish.rs` the selections and polish by
//! the nominal bound and by LinCov.

mod bound_selection;
mod evaluation;
pub mod final_bound;
mod lincov_polish;
mod lincov_selection;
pub mod objective;
pub mod penalty;
pub mod problem;
pub mod site;
pub mod solution;
mod visibility;

pub use bound_selection::BoundSelection;
pub use final_bound::{PCRLB_RUNS, PCRLB_SEED};
pub use lincov_polish::{GroundLinCovSolution, default_lincov_polish};
pub use lincov_selection::LinCovSelection;
pub use objective::GroundObjective;
pub use penalty::{INFEASIBLE_COST, PENALTY_PER_RAD};
pub use problem::{GroundProblem, default_search};
pub use site::Site;
pub use solution::{GroundEvaluation, GroundSolution};
