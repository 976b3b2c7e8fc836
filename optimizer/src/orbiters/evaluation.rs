//! What a constellation is worth: orbiter positions along the trajectory, the integral of the
//! objective with the visibility penalty (eq. 57–62), and the search over elements.

use super::elements::OrbitElements;
use super::objective::LOG_DET_FLOOR;
use super::objective::OrbiterObjective;
use super::problem::OrbiterProblem;
use super::solution::OrbiterEvaluation;
use super::solution::OrbiterSolution;
use crate::error::OptimizerError;
use crate::progress::Progress;
use crate::search::minimize;
use crate::search_options::SearchOptions;
use entrynav::beacons::orbiter_visibility_margin;
use entrynav::math::cross;
use entrynav::math::dot;
use entrynav::math::norm;
use entrynav::math::sub;
use nalgebra::Matrix3;
use nalgebra::Vector3;
use std::f64::consts::PI;
use std::f64::consts::TAU;
use std::time::Instant;

impl OrbiterProblem {
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
