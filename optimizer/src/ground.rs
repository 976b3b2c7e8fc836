//! Ground beacons visible during the whole entry (seed 002 §4.1, eq. 49–54).
//!
//! **Unknowns.** Latitude and longitude of N surface beacons at a common altitude (0 km: on the
//! reference sphere). They turn with the planet (`r_B(t) = R_z(ωt) r_B,fixed`).
//!
//! **Constraint** (eq. 52): each beacon sees the vehicle above its local horizon at every
//! trajectory sample. The visibility margin of [`ground_visibility_margin`] is the vehicle's
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
//! * `Pcrlb` — the final position PCRLB \[m\] of the scenario with these beacons
//!   ([`entrynav::sim::pcrlb_study`]: IMU, dynamics, prior and beacons together, with the truth's
//!   sensors and the epochs of run 0 of seed 1); the search *minimises* its log10. Unlike the
//!   proxies above it is what navigation accuracy at deployment is bounded by. The scenario must
//!   not read external files (it is rebuilt for every candidate).
//!
//! Infeasible sites cost `10⁴ + 10⁴ · Σ_j max(0, min_elevation − elevation_j)` \[rad\]: finite,
//! graded towards the feasible set and worse than every feasible cost.

use crate::output::{BeaconNoise, surface_beacons, template_noise};
use crate::search::{SearchOptions, SearchResult, minimize};
use crate::trajectory::Trajectory;
use crate::{OptimizerError, Progress};
use entrynav::beacons::ground_visibility_margin;
use entrynav::files::FileLoader;
use entrynav::frames::{position_to_spherical, rotate_z, spherical_to_position};
use entrynav::math::{norm, sub};
use entrynav::observability::{
    AnalysisPoint, ChannelSet, DegreeSeries, Method, Scaling, analysis_points, degree_series,
};
use entrynav::scenario::{Scenario, ScenarioConfig};
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::{FRAC_PI_2, PI};
use std::time::Instant;

/// Base cost of an infeasible configuration (above every feasible cost).
pub const INFEASIBLE_COST: f64 = 1e4;
/// Cost per radian of elevation below the required minimum.
pub const PENALTY_PER_RAD: f64 = 1e4;
/// Master seed of the truth run behind [`GroundObjective::Pcrlb`].
pub const PCRLB_SEED: u64 = 1;
/// Truth runs the [`GroundObjective::Pcrlb`] bound averages over (one: common random numbers for
/// every candidate, so the objective is a smooth function of the sites).
pub const PCRLB_RUNS: usize = 1;

/// Final position PCRLB \[m\] of scenario `cfg` on run 0 of seed [`PCRLB_SEED`] (the bound a
/// `trade --seed 1` reports for its first run): the objective of every `--objective pcrlb`.
pub(crate) fn final_position_bound_of(cfg: ScenarioConfig) -> Result<f64, OptimizerError> {
    let name = cfg.name.clone();
    let scenario = Scenario::build(cfg, &entrynav::files::no_files)?;
    let bound = entrynav::sim::pcrlb_study(&scenario, PCRLB_SEED, PCRLB_RUNS)?;
    match bound.final_.get("pos_m").copied().flatten() {
        Some(v) if bound.available && v.is_finite() => Ok(v),
        _ => Err(OptimizerError::InvalidInput(format!(
            "no PCRLB for scenario '{name}': {}",
            bound.reason.as_deref().unwrap_or("non-finite bound")
        ))),
    }
}

/// A ground site (radians, metres).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Site {
    /// Planetocentric latitude \[rad\].
    pub lat: f64,
    /// East longitude \[rad\].
    pub lon: f64,
    /// Altitude above the reference sphere \[m\].
    pub altitude_m: f64,
}

impl Site {
    /// From degrees, on the reference sphere.
    pub fn from_degrees(lat_deg: f64, lon_deg: f64) -> Site {
        Site {
            lat: lat_deg.to_radians(),
            lon: lon_deg.to_radians(),
            altitude_m: 0.0,
        }
    }

    /// [latitude, longitude] in degrees.
    pub fn degrees(&self) -> [f64; 2] {
        [self.lat.to_degrees(), self.lon.to_degrees()]
    }

    /// The same point with latitude in [−π/2, π/2] and longitude in (−π, π].
    pub fn canonical(&self) -> Site {
        let p = spherical_to_position(1.0, self.lon, self.lat);
        let (_, lon, lat) = position_to_spherical(&p);
        Site {
            lat,
            lon,
            altitude_m: self.altitude_m,
        }
    }

    /// Planet-fixed position \[m\] for reference radius `radius`.
    pub fn fixed_position(&self, radius: f64) -> [f64; 3] {
        spherical_to_position(radius + self.altitude_m, self.lon, self.lat)
    }
}

/// What the ground search maximises.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum GroundObjective {
    /// `min_t δ(t)` (seed 002 eq. 49) with this observability method; `scaled` picks the scaled δ
    /// of [`Scaling`] instead of the raw-SI one.
    MinDelta {
        /// How the observability matrix is computed.
        method: Method,
        /// Use the scaled δ (else raw SI, the paper's convention).
        scaled: bool,
    },
    /// `∫ log det F dt` of the range FIM [s · ln m⁻⁶].
    LogDet,
    /// `min_t λ_min(F(t))` [m⁻²].
    MinEig,
    /// Final position PCRLB \[m\] (minimised).
    Pcrlb,
}

impl GroundObjective {
    /// Name used on the command line and in reports: `min-delta`, `logdet`, `min-eig`.
    pub fn name(self) -> &'static str {
        match self {
            GroundObjective::MinDelta { .. } => "min-delta",
            GroundObjective::LogDet => "logdet",
            GroundObjective::MinEig => "min-eig",
            GroundObjective::Pcrlb => "pcrlb",
        }
    }

    /// Unit and meaning of the objective value.
    pub fn units(self) -> String {
        match self {
            GroundObjective::MinDelta { method, scaled } => format!(
                "min over the trajectory of delta = sigma_min/sigma_max of the {} observability \
                 matrix, {} (dimensionless)",
                method.name(),
                if scaled {
                    "scaled (states in characteristic units, rows per noise sigma)"
                } else {
                    "raw SI (states in m, rad, m/s; outputs in m; the papers' convention)"
                }
            ),
            GroundObjective::LogDet => {
                "integral over time of ln det F, F = sum sigma^-2 n n^T the \
                 range FIM of the vehicle position [m^-2]; value in s * ln(m^-6)"
                    .into()
            }
            GroundObjective::MinEig => {
                "min over the trajectory of lambda_min(F), F the range FIM [m^-2]".into()
            }
            GroundObjective::Pcrlb => {
                "final position PCRLB of the scenario with these beacons (IMU, dynamics, prior \
                 and ranges; truth run 0 of seed 1) [m], minimised"
                    .into()
            }
        }
    }
}

/// The objective and constraint data at one set of sites.
#[derive(Debug, Clone, PartialEq)]
pub struct GroundEvaluation {
    /// Objective value (units: [`GroundObjective::units`]); `None` when infeasible.
    pub value: Option<f64>,
    /// Search cost.
    pub cost: f64,
    /// Smallest elevation of the vehicle seen from each site over the trajectory \[rad\].
    pub min_elevation_rad: Vec<f64>,
    /// Every site meets the elevation requirement.
    pub feasible: bool,
}

/// An optimized set of sites.
#[derive(Debug, Clone, PartialEq)]
pub struct GroundSolution {
    /// Canonical sites.
    pub sites: Vec<Site>,
    /// The objective at these sites.
    pub evaluation: GroundEvaluation,
    /// Search statistics.
    pub search: SearchResult,
    /// Wall time of the search \[s\].
    pub elapsed_s: f64,
}

/// The ground-beacon problem on one scenario's nominal trajectory.
#[derive(Debug, Clone)]
pub struct GroundProblem {
    scenario: Scenario,
    points: Vec<AnalysisPoint>,
    trajectory: Trajectory,
    fixed: Vec<[f64; 3]>,
    count: usize,
    objective: GroundObjective,
    noise: BeaconNoise,
    min_elevation: f64,
    altitude_m: f64,
    scaling: Scaling,
    channels: ChannelSet,
}

impl GroundProblem {
    /// `count` beacons on `base`'s nominal trajectory sampled every `step_s` seconds.
    ///
    /// The working scenario is `base` with its beacons replaced by `count` surface beacons that
    /// copy the range (and range-rate) noise of its first ranged beacon; `load` reads files the
    /// scenario refers to. Errors: no range sensor or ranged beacon, `count == 0`.
    pub fn new(
        base: &ScenarioConfig,
        load: &FileLoader<'_>,
        count: usize,
        objective: GroundObjective,
        step_s: f64,
        min_elevation_rad: f64,
    ) -> Result<GroundProblem, OptimizerError> {
        if count == 0 {
            return Err(OptimizerError::InvalidInput(
                "the number of beacons must be at least 1".into(),
            ));
        }
        if !(min_elevation_rad.is_finite() && (0.0..FRAC_PI_2).contains(&min_elevation_rad)) {
            return Err(OptimizerError::InvalidInput(format!(
                "minimum elevation {} deg must be in [0, 90)",
                min_elevation_rad.to_degrees()
            )));
        }
        let noise = template_noise(base, false)?;
        let mut cfg = base.clone();
        let placeholder = vec![Site::from_degrees(0.0, 0.0); count];
        cfg.beacons = surface_beacons(&placeholder, &noise);
        let scenario = Scenario::build(cfg, load)?;
        let points = analysis_points(&scenario, step_s)?;
        if points.len() < 2 {
            return Err(OptimizerError::InvalidInput(format!(
                "scenario '{}' gives {} trajectory sample(s); at least 2 are needed",
                base.name,
                points.len()
            )));
        }
        let trajectory = Trajectory::from_points(&scenario, &points);
        let fixed = (0..trajectory.len())
            .map(|k| trajectory.fixed_position(k))
            .collect();
        let scaling = Scaling::characteristic(scenario.filter_model());
        let channels = ChannelSet::centralised(&scenario);
        Ok(GroundProblem {
            scenario,
            points,
            trajectory,
            fixed,
            count,
            objective,
            noise,
            min_elevation: min_elevation_rad,
            altitude_m: 0.0,
            scaling,
            channels,
        })
    }

    /// Number of beacons.
    pub fn count(&self) -> usize {
        self.count
    }

    /// The objective.
    pub fn objective(&self) -> GroundObjective {
        self.objective
    }

    /// The trajectory.
    pub fn trajectory(&self) -> &Trajectory {
        &self.trajectory
    }

    /// Range noise of the beacons.
    pub fn noise(&self) -> BeaconNoise {
        self.noise
    }

    /// The required minimum elevation \[rad\].
    pub fn min_elevation(&self) -> f64 {
        self.min_elevation
    }

    /// Vehicle positions in the planet-fixed frame at the trajectory samples \[m\].
    pub fn fixed_positions(&self) -> &[[f64; 3]] {
        &self.fixed
    }

    /// The δ scaling of the scenario's filter model.
    pub fn scaling(&self) -> &Scaling {
        &self.scaling
    }

    /// Smallest elevation \[rad\] of the vehicle above the local horizon of `site` over the
    /// trajectory (> 0: visible during the whole entry by eq. 52).
    pub fn min_elevation_of(&self, site: &Site) -> f64 {
        let b = site.fixed_position(self.trajectory.planet.radius);
        self.fixed
            .iter()
            .map(|v| ground_visibility_margin(&b, v))
            .fold(f64::INFINITY, f64::min)
    }

    /// Whether `site` meets the elevation requirement during the whole entry (a margin of
    /// 1e-9 rad keeps the answer strictly inside eq. 52's open region).
    pub fn is_feasible(&self, site: &Site) -> bool {
        self.min_elevation_of(site) >= self.min_elevation + 1e-9
    }

    /// Latitude/longitude of the centre of the smallest visibility cap (below the trajectory's
    /// lowest sample) and the cap's angular radius \[rad\].
    fn smallest_cap(&self) -> (f64, f64, f64) {
        let r_b = self.trajectory.planet.radius + self.altitude_m;
        let (mut best, mut theta) = (0, f64::INFINITY);
        for (k, v) in self.fixed.iter().enumerate() {
            let t = (r_b / norm(v)).clamp(-1.0, 1.0).acos();
            if t < theta {
                (best, theta) = (k, t);
            }
        }
        let (_, lon, lat) = position_to_spherical(&self.fixed[best]);
        (lat, lon, theta)
    }

    /// Feasible sites on the lattice of multiples of `grid_deg` degrees in latitude and
    /// longitude (longitude in (−180°, 180°]). Errors when no lattice point is feasible.
    pub fn visible_grid(&self, grid_deg: f64) -> Result<Vec<Site>, OptimizerError> {
        if !(grid_deg.is_finite() && grid_deg > 0.0 && grid_deg <= 30.0) {
            return Err(OptimizerError::InvalidInput(format!(
                "grid spacing {grid_deg} deg must be in (0, 30]"
            )));
        }
        let (lat_c, lon_c, theta) = self.smallest_cap();
        let step = grid_deg.to_radians();
        let lat_lo = ((lat_c - theta) / step).floor() as i64;
        let lat_hi = ((lat_c + theta) / step).ceil() as i64;
        let mut out = Vec::new();
        for i in lat_lo..=lat_hi {
            let lat = i as f64 * step;
            if lat.abs() > FRAC_PI_2 {
                continue;
            }
            let cos_lat = lat.cos().max(1e-6);
            let half = (theta / cos_lat).min(PI);
            let lon_lo = ((lon_c - half) / step).floor() as i64;
            let lon_hi = ((lon_c + half) / step).ceil() as i64;
            for j in lon_lo..=lon_hi {
                let site = Site {
                    lat,
                    lon: j as f64 * step,
                    altitude_m: self.altitude_m,
                }
                .canonical();
                if self.is_feasible(&site) && !out.iter().any(|s: &Site| same_site(s, &site)) {
                    out.push(site);
                }
            }
        }
        if out.is_empty() {
            return Err(self.no_site_error());
        }
        Ok(out)
    }

    fn no_site_error(&self) -> OptimizerError {
        OptimizerError::Infeasible(format!(
            "no site is visible during the whole entry of scenario '{}' with a minimum elevation \
             of {:.3} deg (eq. 52: the vehicle must stay above every beacon's horizon from t = 0 \
             to t = {} s)",
            self.scenario.config.name,
            self.min_elevation.to_degrees(),
            self.trajectory.times.last().copied().unwrap_or(0.0)
        ))
    }

    /// Search box `[lat, lon]` per site (radians, longitude unwrapped around the smallest cap):
    /// the bounding box of the feasible points of a fine lattice, widened by one cell.
    pub fn bounds(&self) -> Result<(Vec<f64>, Vec<f64>), OptimizerError> {
        let (lat_c, lon_c, theta) = self.smallest_cap();
        let n = 80;
        let cell = 2.0 * theta / n as f64;
        let (mut lat_lo, mut lat_hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let (mut lon_lo, mut lon_hi) = (f64::INFINITY, f64::NEG_INFINITY);
        let cos_lat = lat_c.cos().max(1e-3);
        let lon_cell = (cell / cos_lat).min(PI / n as f64);
        for i in 0..=n {
            let lat = lat_c - theta + i as f64 * cell;
            for j in 0..=n {
                let lon = lon_c + (j as f64 - n as f64 / 2.0) * lon_cell;
                let site = Site {
                    lat,
                    lon,
                    altitude_m: self.altitude_m,
                };
                if lat.abs() <= FRAC_PI_2 && self.is_feasible(&site) {
                    lat_lo = lat_lo.min(lat);
                    lat_hi = lat_hi.max(lat);
                    lon_lo = lon_lo.min(lon);
                    lon_hi = lon_hi.max(lon);
                }
            }
        }
        if !lat_lo.is_finite() {
            return Err(self.no_site_error());
        }
        let (lat_lo, lat_hi) = (
            (lat_lo - cell).max(-FRAC_PI_2),
            (lat_hi + cell).min(FRAC_PI_2),
        );
        let (lon_lo, lon_hi) = (lon_lo - lon_cell, lon_hi + lon_cell);
        let lower = (0..self.count).flat_map(|_| [lat_lo, lon_lo]).collect();
        let upper = (0..self.count).flat_map(|_| [lat_hi, lon_hi]).collect();
        Ok((lower, upper))
    }

    /// Sites from the search vector `[lat₁, lon₁, lat₂, …]` (radians).
    pub fn sites_from(&self, x: &[f64]) -> Vec<Site> {
        x.chunks_exact(2)
            .map(|c| Site {
                lat: c[0],
                lon: c[1],
                altitude_m: self.altitude_m,
            })
            .collect()
    }

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
            GroundObjective::Pcrlb => self.final_position_bound(sites)?,
        })
    }

    /// Final position PCRLB \[m\] of the working scenario with beacons at `sites` (one truth
    /// run: seed 1, run 0, the first run of a `trade --seed 1`).
    pub fn final_position_bound(&self, sites: &[Site]) -> Result<f64, OptimizerError> {
        let mut cfg = self.scenario.config.clone();
        cfg.beacons = surface_beacons(sites, &self.noise);
        final_position_bound_of(cfg)
    }

    fn cost_of_value(&self, v: f64) -> f64 {
        match self.objective {
            GroundObjective::MinDelta { .. } | GroundObjective::MinEig => -v.max(1e-300).log10(),
            GroundObjective::LogDet => -v / self.trajectory.duration(),
            GroundObjective::Pcrlb => v.max(1e-300).log10(),
        }
    }

    /// Evaluate `sites`: elevations, feasibility, objective and search cost.
    pub fn evaluate(&self, sites: &[Site]) -> Result<GroundEvaluation, OptimizerError> {
        self.check_count(sites)?;
        let min_elevation_rad: Vec<f64> = sites.iter().map(|s| self.min_elevation_of(s)).collect();
        let shortfall: f64 = min_elevation_rad
            .iter()
            .map(|e| (self.min_elevation + 1e-9 - e).max(0.0))
            .sum();
        let feasible = shortfall == 0.0;
        if !feasible {
            return Ok(GroundEvaluation {
                value: None,
                cost: INFEASIBLE_COST + PENALTY_PER_RAD * shortfall,
                min_elevation_rad,
                feasible,
            });
        }
        let v = self.value(sites)?;
        Ok(GroundEvaluation {
            value: Some(v),
            cost: self.cost_of_value(v),
            min_elevation_rad,
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
            return Err(self.no_site_error());
        }
        Ok(GroundSolution {
            sites,
            evaluation,
            search,
            elapsed_s: started.elapsed().as_secs_f64(),
        })
    }
}

fn same_site(a: &Site, b: &Site) -> bool {
    (a.lat - b.lat).abs() < 1e-12 && (a.lon - b.lon).abs() < 1e-12
}

/// Default search budget for the ground problem.
pub fn default_search(seed: u64) -> SearchOptions {
    SearchOptions {
        seed,
        starts: 4,
        particles: 24,
        iterations: 60,
        polish_iterations: 150,
        polish_step: 0.05,
    }
}
