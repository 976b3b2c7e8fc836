//! [`OrbiterProblem`]: relay orbiters at a common altitude over one scenario's nominal
//! trajectory (its settings and accessors; the evaluation and search are in `evaluation.rs`), the
//! default visibility penalty and search budget.

use super::objective::OrbiterObjective;
use crate::error::OptimizerError;
use crate::search_options::SearchOptions;
use crate::trajectory::Trajectory;
use entrynav::math::norm;
use std::f64::consts::PI;

/// Default penalty per radian of horizon violation per second.
pub const DEFAULT_PENALTY_PER_RAD_S: f64 = 100.0;

/// The orbiter-geometry problem on one trajectory.
#[derive(Debug, Clone)]
pub struct OrbiterProblem {
    pub(super) trajectory: Trajectory,
    pub(super) count: usize,
    pub(super) altitude_m: f64,
    pub(super) objective: OrbiterObjective,
    /// Penalty weight c per radian of horizon violation per second.
    pub penalty_per_rad_s: f64,
    pub(super) radius: f64,
    pub(super) cos_nt: Vec<f64>,
    pub(super) sin_nt: Vec<f64>,
    /// θ₀(t_k) + θ₁ of eq. 58–60 per sample \[rad\].
    pub(super) horizon: Vec<f64>,
    /// cos of `horizon` (−1 when the sum exceeds π: always in view).
    pub(super) cos_horizon: Vec<f64>,
    /// Unit vectors along the vehicle position.
    pub(super) vehicle_dir: Vec<[f64; 3]>,
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
