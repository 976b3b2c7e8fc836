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
//! [`orbiter_visibility_margin`] and `c` = [`OrbiterProblem::penalty_per_rad_s`].
//!
//! Files: `mod.rs` the objective and the problem; `elements.rs` the unknowns of one orbiter;
//! `evaluation.rs` positions, the objective along the trajectory and the search.

use crate::search::{SearchOptions, SearchResult, minimize};
use crate::trajectory::Trajectory;
use crate::{OptimizerError, Progress};
use entrynav::beacons::{CircularOrbit, Orbiter, orbiter_visibility_margin};
use entrynav::math::{cross, dot, norm, sub};
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::{PI, TAU};
use std::time::Instant;

mod elements;
mod evaluation;

pub use elements::OrbitElements;

/// Smallest determinant taken inside the logarithm of [`OrbiterObjective::LogDet`].
pub const LOG_DET_FLOOR: f64 = 1e-9;

/// Default penalty per radian of horizon violation per second.
pub const DEFAULT_PENALTY_PER_RAD_S: f64 = 100.0;

/// What is integrated along the trajectory.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum OrbiterObjective {
    /// `∫ det(N₃) dt` (seed 002 eq. 57, 62), three orbiters only.
    DetN3,
    /// `∫ log max(det F, 10⁻⁹) dt`, any number ≥ 3.
    LogDet,
}

impl OrbiterObjective {
    /// The paper's choice: [`OrbiterObjective::DetN3`] for three orbiters, else
    /// [`OrbiterObjective::LogDet`].
    pub fn default_for(count: usize) -> OrbiterObjective {
        if count == 3 {
            OrbiterObjective::DetN3
        } else {
            OrbiterObjective::LogDet
        }
    }

    /// Name used in reports: `integral-det-N3` or `integral-logdet-fim`.
    pub fn name(self) -> &'static str {
        match self {
            OrbiterObjective::DetN3 => "integral-det-N3",
            OrbiterObjective::LogDet => "integral-logdet-fim",
        }
    }

    /// Upper bound of the objective per second of trajectory: 1 for det(N₃), `3 log(n/3)` for
    /// log det (seed 002 eq. 40).
    pub fn max_rate(self, count: usize) -> f64 {
        match self {
            OrbiterObjective::DetN3 => 1.0,
            OrbiterObjective::LogDet => 3.0 * (count as f64 / 3.0).ln(),
        }
    }
}

/// The objective and its constraint data at one geometry.
#[derive(Debug, Clone, PartialEq)]
pub struct OrbiterEvaluation {
    /// Objective J (penalty-free; hidden orbiters contribute nothing).
    pub value: f64,
    /// Integrand at each trajectory sample (`det F` or `log max(det F, 10⁻⁹)`).
    pub integrand: Vec<f64>,
    /// Smallest visibility margin over orbiters and samples \[rad\] (> 0: all always visible).
    pub min_margin_rad: f64,
    /// `∫ Σ_j max(0, −m_j) dt` [rad·s].
    pub violation_rad_s: f64,
    /// Fraction of (orbiter, sample) pairs in line of sight.
    pub visible_fraction: f64,
    /// The cost the search minimises: `−J + c · violation`.
    pub cost: f64,
}

/// An optimized constellation.
#[derive(Debug, Clone, PartialEq)]
pub struct OrbiterSolution {
    /// Canonical elements of each orbiter.
    pub elements: Vec<OrbitElements>,
    /// The objective at these elements.
    pub evaluation: OrbiterEvaluation,
    /// Search statistics.
    pub search: SearchResult,
    /// Wall time of the search \[s\].
    pub elapsed_s: f64,
}

/// The orbiter-geometry problem on one trajectory.
#[derive(Debug, Clone)]
pub struct OrbiterProblem {
    trajectory: Trajectory,
    count: usize,
    altitude_m: f64,
    objective: OrbiterObjective,
    /// Penalty weight c per radian of horizon violation per second.
    pub penalty_per_rad_s: f64,
    radius: f64,
    cos_nt: Vec<f64>,
    sin_nt: Vec<f64>,
    /// θ₀(t_k) + θ₁ of eq. 58–60 per sample \[rad\].
    horizon: Vec<f64>,
    /// cos of `horizon` (−1 when the sum exceeds π: always in view).
    cos_horizon: Vec<f64>,
    /// Unit vectors along the vehicle position.
    vehicle_dir: Vec<[f64; 3]>,
}

impl OrbiterProblem {
    /// `count` orbiters at `altitude_m` above the reference sphere, objective `objective`
    /// (default: [`OrbiterObjective::default_for`]).
    ///
    /// Errors: altitude not above the surface, fewer than three orbiters (the position FIM is
    /// singular for any geometry), `DetN3` with a count other than three, an empty trajectory.
    pub fn new(
        trajectory: Trajectory,
        count: usize,
        altitude_m: f64,
        objective: Option<OrbiterObjective>,
    ) -> Result<OrbiterProblem, OptimizerError> {
        if !(altitude_m.is_finite() && altitude_m > 0.0) {
            return Err(OptimizerError::Infeasible(format!(
                "orbit altitude {} km is at or below the surface (must be > 0 km above the \
                 {} km reference sphere)",
                altitude_m / 1e3,
                trajectory.planet.radius / 1e3
            )));
        }
        if count < 3 {
            return Err(OptimizerError::Infeasible(format!(
                "{count} orbiter(s): ranges to fewer than 3 orbiters leave the position FIM \
                 singular for every geometry (det = 0); use at least 3"
            )));
        }
        let objective = objective.unwrap_or(OrbiterObjective::default_for(count));
        if objective == OrbiterObjective::DetN3 && count != 3 {
            return Err(OptimizerError::InvalidInput(format!(
                "the det(N3) objective (seed 002 eq. 57) is defined for 3 orbiters, not {count}; \
                 use the log-det objective"
            )));
        }
        if trajectory.len() < 2 {
            return Err(OptimizerError::InvalidInput(
                "the trajectory needs at least 2 samples".into(),
            ));
        }
        let radius = trajectory.planet.radius + altitude_m;
        let mean_motion = (trajectory.planet.mu / radius.powi(3)).sqrt();
        let (sin_nt, cos_nt) = trajectory
            .times
            .iter()
            .map(|t| (mean_motion * t).sin_cos())
            .unzip();
        // Horizon half-angles as in `orbiter_visibility_margin` (ratios clamped to [−1, 1]).
        let theta1 = (trajectory.planet.radius / radius).clamp(-1.0, 1.0).acos();
        let horizon: Vec<f64> = trajectory
            .positions
            .iter()
            .map(|p| {
                let r = norm(p);
                (trajectory.planet.radius / r).clamp(-1.0, 1.0).acos() + theta1
            })
            .collect();
        let cos_horizon = horizon
            .iter()
            .map(|h| if *h >= PI { -1.0 } else { h.cos() })
            .collect();
        let vehicle_dir = trajectory
            .positions
            .iter()
            .map(|p| {
                let r = norm(p);
                [p[0] / r, p[1] / r, p[2] / r]
            })
            .collect();
        Ok(OrbiterProblem {
            horizon,
            cos_horizon,
            vehicle_dir,
            trajectory,
            count,
            altitude_m,
            objective,
            penalty_per_rad_s: DEFAULT_PENALTY_PER_RAD_S,
            radius,
            cos_nt,
            sin_nt,
        })
    }

    /// Number of orbiters.
    pub fn count(&self) -> usize {
        self.count
    }

    /// Orbit altitude \[m\].
    pub fn altitude_m(&self) -> f64 {
        self.altitude_m
    }

    /// The objective.
    pub fn objective(&self) -> OrbiterObjective {
        self.objective
    }

    /// The trajectory.
    pub fn trajectory(&self) -> &Trajectory {
        &self.trajectory
    }

    /// Largest possible objective: `max_rate × duration` (240 for det(N₃) over 240 s).
    pub fn upper_bound(&self) -> f64 {
        self.objective.max_rate(self.count) * self.trajectory.duration()
    }
}

/// Default search budget for the orbiter problem (tuned on `orbiters-3`: about 1.1e5 evaluations,
/// under a second of wall time on two cores; seeds 1–6 all reach 239.84 ± 0.01, above the paper's
/// 237.963).
pub fn default_search(seed: u64) -> SearchOptions {
    SearchOptions {
        seed,
        starts: 8,
        particles: 40,
        iterations: 150,
        polish_iterations: 600,
        polish_step: 0.02,
    }
}
