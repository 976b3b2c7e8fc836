//! What a set of ground sites is worth: δ(t) and the FIM along the entry, the objective's value,
//! its cost with the visibility penalty, and the search over sites.

use super::objective::GroundObjective;
use super::penalty::INFEASIBLE_COST;
use super::penalty::PENALTY_PER_RAD;
use super::problem::GroundProblem;
use super::site::Site;
use super::solution::GroundEvaluation;
use super::solution::GroundSolution;
use crate::error::OptimizerError;
use crate::progress::Progress;
use crate::search::minimize;
use crate::search_options::SearchOptions;
use entrynav::beacons::ground_visibility_margin;
use entrynav::frames::rotate_z;
use entrynav::frames::spherical_to_position;
use entrynav::math::norm;
use entrynav::math::sub;
use entrynav::observability::AnalysisPoint;
use entrynav::observability::DegreeSeries;
use entrynav::observability::Method;
use entrynav::observability::degree_series;
use entrynav::sim::bounds::nominal_bound::NominalBound;
use entrynav::sim::bounds::nominal_bound::NominalBoundSeries;
use entrynav::sim::bounds::nominal_bound::RangeSite;
use nalgebra::Matrix3;
use nalgebra::Vector3;
use std::f64::consts::PI;
use std::time::Instant;

impl GroundProblem {
    /// The analysis points with the beacons placed at `sites` (availability by eq. 52).
    pub fn points_with(&self, sites: &[Site]) -> Vec<AnalysisPoint> {
        let radius = self.trajectory.planet.radius;
        let w = self.trajectory.omega;
        let fixed: Vec<[f64; 3]> = sites.iter().map(|s| s.fixed_position(radius)).collect();
        self.points
            .iter()
            .zip(&self.fixed)
            .map(|(p, v)| {
                let mut q = p.clone();
                q.beacons = fixed
                    .iter()
                    .map(|b| {
                        let r = rotate_z(b, w * p.t);
                        (r, [-w * r[1], w * r[0], 0.0])
                    })
                    .collect();
                q.available = fixed
                    .iter()
                    .map(|b| ground_visibility_margin(b, v) > 0.0)
                    .collect();
                q
            })
            .collect()
    }

    /// δ(t) for beacons at `sites` (the same count as the problem's), by `method`.
    pub fn delta_series(
        &self,
        sites: &[Site],
        method: Method,
    ) -> Result<DegreeSeries, OptimizerError> {
        self.check_count(sites)?;
        let points = self.points_with(sites);
        Ok(degree_series(
            &self.scenario,
            &points,
            &self.channels,
            method,
            &self.scaling,
        )?)
    }

    /// Range FIM of the vehicle position at each sample [m⁻²] (visible beacons only).
    pub fn fim_series(&self, sites: &[Site]) -> Vec<Matrix3<f64>> {
        let radius = self.trajectory.planet.radius;
        let s2 = self.noise.range_sigma_m.powi(-2);
        let fixed: Vec<[f64; 3]> = sites.iter().map(|s| s.fixed_position(radius)).collect();
        self.fixed
            .iter()
            .map(|v| {
                fixed.iter().fold(Matrix3::zeros(), |acc, b| {
                    if ground_visibility_margin(b, v) <= 0.0 {
                        return acc;
                    }
                    let d = sub(v, b);
                    let u = Vector3::from(d) / norm(&d);
                    acc + u * u.transpose() * s2
                })
            })
            .collect()
    }

    fn check_count(&self, sites: &[Site]) -> Result<(), OptimizerError> {
        if sites.len() != self.count {
            return Err(OptimizerError::InvalidInput(format!(
                "{} site(s) given for a {}-beacon problem",
                sites.len(),
                self.count
            )));
        }
        Ok(())
    }

    /// Objective value of feasible `sites` (no feasibility test).
    fn value(&self, sites: &[Site]) -> Result<f64, OptimizerError> {
        Ok(match self.objective {
            GroundObjective::MinDelta { method, scaled } => self
                .delta_series(sites, method)?
                .summary(scaled)
                .map_or(0.0, |s| s.min),
            GroundObjective::LogDet => {
                let f = self.fim_series(sites);
                f.iter()
                    .zip(&self.trajectory.weights)
                    .map(|(m, w)| w * m.determinant().max(1e-300).ln())
                    .sum()
            }
            GroundObjective::MinEig => self
                .fim_series(sites)
                .iter()
                .map(|m| m.symmetric_eigenvalues().min().max(0.0))
                .fold(f64::INFINITY, f64::min),
            GroundObjective::PcrlbAvg => self.bound_series(sites)?.time_avg(),
            GroundObjective::PcrlbFinal => self.bound_series(sites)?.final_value(),
            GroundObjective::Navigation => {
                let (avg, last) = self.reference.ok_or_else(|| {
                    OptimizerError::InvalidInput(
                        "the navigation objective needs the input design (with_reference)".into(),
                    )
                })?;
                let s = self.bound_series(sites)?;
                0.5 * (s.time_avg() / avg + s.final_value() / last)
            }
        })
    }

    /// The nominal position bound with beacons at `sites` (the problem's count).
    pub fn bound_series(&self, sites: &[Site]) -> Result<NominalBoundSeries, OptimizerError> {
        self.check_count(sites)?;
        self.bound_series_of(sites)
    }

    /// The nominal position bound with beacons at `sites` (any count), each with the problem's
    /// range noise and elevation mask; available whatever the objective (set up on first use
    /// otherwise).
    pub fn bound_series_of(&self, sites: &[Site]) -> Result<NominalBoundSeries, OptimizerError> {
        self.bound_series_masked(sites, self.elevation_mask)
    }

    /// [`Self::bound_series_of`] with elevation mask `mask_rad` (e.g. the input design's own).
    pub fn bound_series_masked(
        &self,
        sites: &[Site],
        mask_rad: f64,
    ) -> Result<NominalBoundSeries, OptimizerError> {
        let radius = self.trajectory.planet.radius;
        let range: Vec<RangeSite> = sites
            .iter()
            .map(|s| RangeSite {
                position_m: s.fixed_position(radius),
                sigma_m: self.noise.range_sigma_m,
                elevation_mask_rad: mask_rad,
            })
            .collect();
        let built;
        let nominal = match &self.nominal {
            Some(n) => n,
            None => {
                built = NominalBound::new(&self.scenario)?;
                &built
            }
        };
        Ok(nominal.ground_sites(&range)?)
    }

    /// The smallest great-circle separation between two of `sites` \[rad\].
    pub(super) fn closest_pair(sites: &[Site]) -> Option<f64> {
        let mut best: Option<f64> = None;
        for (i, a) in sites.iter().enumerate() {
            for b in &sites[i + 1..] {
                let pa = spherical_to_position(1.0, a.lon, a.lat);
                let pb = spherical_to_position(1.0, b.lon, b.lat);
                let d = entrynav::math::norm(&entrynav::math::cross(&pa, &pb))
                    .atan2(entrynav::math::dot(&pa, &pb));
                best = Some(best.map_or(d, |m: f64| m.min(d)));
            }
        }
        best
    }

    fn cost_of_value(&self, v: f64) -> f64 {
        match self.objective {
            GroundObjective::MinDelta { .. } | GroundObjective::MinEig => -v.max(1e-300).log10(),
            GroundObjective::LogDet => -v / self.trajectory.duration(),
            GroundObjective::PcrlbAvg
            | GroundObjective::PcrlbFinal
            | GroundObjective::Navigation => v.max(1e-300).log10(),
        }
    }

    /// Evaluate `sites`: elevations, feasibility, objective and search cost.
    pub fn evaluate(&self, sites: &[Site]) -> Result<GroundEvaluation, OptimizerError> {
        self.check_count(sites)?;
        let min_elevation_rad: Vec<f64> = sites.iter().map(|s| self.min_elevation_of(s)).collect();
        let mut shortfall: f64 = sites.iter().map(|s| self.visibility_shortfall(s)).sum();
        let closest_pair_rad = Self::closest_pair(sites);
        if self.min_separation > 0.0 {
            let canon: Vec<Site> = sites.iter().map(Site::canonical).collect();
            for (i, a) in canon.iter().enumerate() {
                for b in &canon[i + 1..] {
                    let d = Self::closest_pair(&[*a, *b]).unwrap_or(PI);
                    shortfall += (self.min_separation - d).max(0.0);
                }
            }
        }
        let feasible = shortfall == 0.0;
        if !feasible {
            return Ok(GroundEvaluation {
                value: None,
                cost: INFEASIBLE_COST + PENALTY_PER_RAD * shortfall,
                min_elevation_rad,
                closest_pair_rad,
                feasible,
            });
        }
        let v = self.value(sites)?;
        Ok(GroundEvaluation {
            value: Some(v),
            cost: self.cost_of_value(v),
            min_elevation_rad,
            closest_pair_rad,
            feasible,
        })
    }

    /// The search cost at `x = [lat₁, lon₁, …]` (finite; errors become the infeasible cost).
    pub fn cost(&self, x: &[f64]) -> f64 {
        match self.evaluate(&self.sites_from(x)) {
            Ok(e) => e.cost,
            Err(_) => 2.0 * INFEASIBLE_COST,
        }
    }

    /// Seeded particle swarm + Nelder–Mead search (see [`crate::search`]).
    pub fn optimize(
        &self,
        opts: &SearchOptions,
        progress: Progress<'_>,
    ) -> Result<GroundSolution, OptimizerError> {
        let started = Instant::now();
        let (lower, upper) = self.bounds()?;
        let cost = |x: &[f64]| self.cost(x);
        let search = minimize(&cost, &lower, &upper, opts, progress)?;
        let sites: Vec<Site> = self
            .sites_from(&search.x)
            .iter()
            .map(Site::canonical)
            .collect();
        let evaluation = self.evaluate(&sites)?;
        if !evaluation.feasible {
            // Feasible sites exist (`bounds` found them): the search was too small to reach one.
            return Err(OptimizerError::Infeasible(format!(
                "the search ended on an infeasible design of scenario '{}' after {} start(s) of \
                 {} particle(s), {} iteration(s) and {} polish iteration(s); feasible sites \
                 exist, so give it more (starts, particles, iterations, polish_iterations)",
                self.scenario.config.name,
                opts.starts,
                opts.particles,
                opts.iterations,
                opts.polish_iterations
            )));
        }
        Ok(GroundSolution {
            sites,
            evaluation,
            search,
            elapsed_s: started.elapsed().as_secs_f64(),
        })
    }
}
