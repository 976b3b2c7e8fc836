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

use crate::search::{SearchOptions, SearchResult, minimize};
use crate::trajectory::Trajectory;
use crate::{OptimizerError, Progress};
use entrynav::beacons::{CircularOrbit, Orbiter, orbiter_visibility_margin};
use entrynav::math::{cross, dot, norm, sub};
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::{PI, TAU};
use std::time::Instant;

/// Smallest determinant taken inside the logarithm of [`OrbiterObjective::LogDet`].
pub const LOG_DET_FLOOR: f64 = 1e-9;

/// Default penalty per radian of horizon violation per second.
pub const DEFAULT_PENALTY_PER_RAD_S: f64 = 100.0;

/// The circular-orbit unknowns of one orbiter (radians).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitElements {
    /// Longitude of the ascending node Ω \[rad\].
    pub raan: f64,
    /// Inclination i \[rad\].
    pub inc: f64,
    /// Argument of latitude f at t = 0 \[rad\].
    pub true_anomaly: f64,
}

fn wrap_tau(a: f64) -> f64 {
    let w = a.rem_euclid(TAU);
    if w >= TAU { 0.0 } else { w }
}

impl OrbitElements {
    /// From (Ω, i, f) in degrees.
    pub fn from_degrees(raan_deg: f64, inc_deg: f64, true_anomaly_deg: f64) -> OrbitElements {
        OrbitElements {
            raan: raan_deg.to_radians(),
            inc: inc_deg.to_radians(),
            true_anomaly: true_anomaly_deg.to_radians(),
        }
    }

    /// (Ω, i, f) in degrees.
    pub fn degrees(&self) -> [f64; 3] {
        [
            self.raan.to_degrees(),
            self.inc.to_degrees(),
            self.true_anomaly.to_degrees(),
        ]
    }

    /// The same orbit and phase with Ω, f in [0, 2π) and i in [0, π].
    ///
    /// `(Ω, −i, f)` and `(Ω + π, 2π − i, f + π)` describe the same motion as `(Ω + π, i, f + π)`
    /// and `(Ω, i, f)` respectively (P and Q change sign together), which folds any real
    /// inclination into [0, π].
    pub fn canonical(&self) -> OrbitElements {
        let mut inc = self.inc.rem_euclid(TAU);
        let (mut raan, mut f) = (self.raan, self.true_anomaly);
        if inc > PI {
            inc = TAU - inc;
            raan += PI;
            f += PI;
        }
        OrbitElements {
            raan: wrap_tau(raan),
            inc,
            true_anomaly: wrap_tau(f),
        }
    }

    /// Perifocal unit vectors P, Q of seed 002 eq. 56.
    pub fn basis(&self) -> ([f64; 3], [f64; 3]) {
        let (so, co) = self.raan.sin_cos();
        let (si, ci) = self.inc.sin_cos();
        ([co, so, 0.0], [-so * ci, co * ci, si])
    }

    /// The orbiter as the core library models it (for cross-checks and scenario files).
    pub fn orbiter(
        &self,
        planet: &entrynav::Planet,
        altitude_m: f64,
    ) -> Result<Orbiter, OptimizerError> {
        Ok(Orbiter::from_circular(
            planet,
            &CircularOrbit {
                altitude: altitude_m,
                raan: self.raan,
                inc: self.inc,
                true_anomaly: self.true_anomaly,
            },
        )?)
    }
}

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

    /// Inertial position of an orbiter at sample `k` \[m\].
    pub fn orbiter_position(&self, el: &OrbitElements, k: usize) -> [f64; 3] {
        let (p, q) = el.basis();
        let (sf, cf) = el.true_anomaly.sin_cos();
        self.position_from(&p, &q, sf, cf, k)
    }

    #[inline]
    fn position_from(&self, p: &[f64; 3], q: &[f64; 3], sf: f64, cf: f64, k: usize) -> [f64; 3] {
        // cos(f + nt), sin(f + nt) by the addition theorems.
        let c = cf * self.cos_nt[k] - sf * self.sin_nt[k];
        let s = sf * self.cos_nt[k] + cf * self.sin_nt[k];
        let r = self.radius;
        [
            r * (c * p[0] + s * q[0]),
            r * (c * p[1] + s * q[1]),
            r * (c * p[2] + s * q[2]),
        ]
    }

    /// Elements from the search vector `[Ω₁, i₁, f₁, Ω₂, …]` (radians).
    pub fn elements_from(&self, x: &[f64]) -> Vec<OrbitElements> {
        x.chunks_exact(3)
            .map(|c| OrbitElements {
                raan: c[0],
                inc: c[1],
                true_anomaly: c[2],
            })
            .collect()
    }

    /// Evaluate the objective, the integrand and the visibility data at `elements` (one per
    /// orbiter; extra or missing entries are an error).
    pub fn evaluate(
        &self,
        elements: &[OrbitElements],
    ) -> Result<OrbiterEvaluation, OptimizerError> {
        if elements.len() != self.count {
            return Err(OptimizerError::InvalidInput(format!(
                "{} orbit(s) given for a {}-orbiter problem",
                elements.len(),
                self.count
            )));
        }
        Ok(self.evaluate_unchecked(elements, true))
    }

    /// The search cost at `x = [Ω₁, i₁, f₁, …]`: `−J + c · violation` (finite for finite x).
    pub fn cost(&self, x: &[f64]) -> f64 {
        self.evaluate_unchecked(&self.elements_from(x), false).cost
    }

    fn evaluate_unchecked(&self, elements: &[OrbitElements], keep: bool) -> OrbiterEvaluation {
        let tr = &self.trajectory;
        let planet_r = tr.planet.radius;
        let orbits: Vec<([f64; 3], [f64; 3], f64, f64)> = elements
            .iter()
            .map(|e| {
                let (p, q) = e.basis();
                let (sf, cf) = e.true_anomaly.sin_cos();
                (p, q, sf, cf)
            })
            .collect();
        let mut integrand = Vec::with_capacity(if keep { tr.len() } else { 0 });
        let mut value = 0.0;
        let mut violation = 0.0;
        let mut min_margin = f64::INFINITY;
        let mut visible_pairs = 0usize;
        let mut dirs: Vec<[f64; 3]> = Vec::with_capacity(self.count);
        for k in 0..tr.len() {
            let v = tr.positions[k];
            dirs.clear();
            let mut viol_k = 0.0;
            for (p, q, sf, cf) in &orbits {
                let b = self.position_from(p, q, *sf, *cf, k);
                // The margin θ₀ + θ₁ − θ of eq. 58–60; the search only needs it when the orbiter
                // is hidden (cos θ ≤ cos(θ₀ + θ₁)), reports need it always.
                let cos_theta = dot(&self.vehicle_dir[k], &b) / self.radius;
                let visible = cos_theta > self.cos_horizon[k];
                let m = if keep {
                    orbiter_visibility_margin(&b, &v, planet_r)
                } else if visible {
                    f64::INFINITY
                } else {
                    self.horizon[k] - cos_theta.clamp(-1.0, 1.0).acos()
                };
                min_margin = min_margin.min(m);
                if visible && m > 0.0 {
                    let d = sub(&v, &b);
                    let r = norm(&d);
                    if r > 0.0 {
                        dirs.push([d[0] / r, d[1] / r, d[2] / r]);
                        visible_pairs += 1;
                    }
                } else {
                    viol_k += (-m).max(0.0);
                }
            }
            let g = match self.objective {
                OrbiterObjective::DetN3 => {
                    if dirs.len() == 3 {
                        dot(&dirs[0], &cross(&dirs[1], &dirs[2])).powi(2)
                    } else {
                        0.0
                    }
                }
                OrbiterObjective::LogDet => {
                    let f = dirs.iter().fold(Matrix3::zeros(), |acc, d| {
                        let u = Vector3::from(*d);
                        acc + u * u.transpose()
                    });
                    f.determinant().max(LOG_DET_FLOOR).ln()
                }
            };
            let w = tr.weights[k];
            value += w * g;
            violation += w * viol_k;
            if keep {
                integrand.push(g);
            }
        }
        let cost = -value + self.penalty_per_rad_s * violation;
        OrbiterEvaluation {
            value,
            integrand,
            min_margin_rad: min_margin,
            violation_rad_s: violation,
            visible_fraction: visible_pairs as f64 / (tr.len() * self.count).max(1) as f64,
            cost,
        }
    }

    /// Search box: Ω, f ∈ [0, 2π], i ∈ [0, π] for every orbiter.
    pub fn bounds(&self) -> (Vec<f64>, Vec<f64>) {
        let lower = vec![0.0; 3 * self.count];
        let upper = (0..self.count).flat_map(|_| [TAU, PI, TAU]).collect();
        (lower, upper)
    }

    /// Seeded particle swarm + Nelder–Mead search (see [`crate::search`]).
    pub fn optimize(
        &self,
        opts: &SearchOptions,
        progress: Progress<'_>,
    ) -> Result<OrbiterSolution, OptimizerError> {
        let started = Instant::now();
        let (lower, upper) = self.bounds();
        let cost = |x: &[f64]| self.cost(x);
        let search = minimize(&cost, &lower, &upper, opts, progress)?;
        let elements: Vec<OrbitElements> = self
            .elements_from(&search.x)
            .iter()
            .map(OrbitElements::canonical)
            .collect();
        let evaluation = self.evaluate(&elements)?;
        Ok(OrbiterSolution {
            elements,
            evaluation,
            search,
            elapsed_s: started.elapsed().as_secs_f64(),
        })
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn canonical_elements_describe_the_same_motion() {
        let planet = entrynav::Planet::MARS;
        let alt = 725e3;
        for el in [
            OrbitElements::from_degrees(10.0, -30.0, 100.0),
            OrbitElements::from_degrees(-50.0, 250.0, 700.0),
            OrbitElements::from_degrees(400.0, 90.0, -20.0),
        ] {
            let c = el.canonical();
            assert!((0.0..=PI).contains(&c.inc));
            assert!((0.0..TAU).contains(&c.raan) && (0.0..TAU).contains(&c.true_anomaly));
            let (ra, va) = el.orbiter(&planet, alt).unwrap().initial_state();
            let (rb, vb) = c.orbiter(&planet, alt).unwrap().initial_state();
            for k in 0..3 {
                assert!((ra[k] - rb[k]).abs() < 1e-6, "{el:?} {c:?}");
                assert!((va[k] - vb[k]).abs() < 1e-9);
            }
        }
    }
}
