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
//! Files: `mod.rs` the sites, objectives and problem; `visibility.rs` eq. 52, the visible grid
//! and the search box; `evaluation.rs` δ(t), the FIM, values, costs and the search.

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
use entrynav::sim::bounds::nominal_bound::{NominalBound, NominalBoundSeries, RangeSite};
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::{FRAC_PI_2, PI};
use std::time::Instant;

mod bound_selection;
mod evaluation;
mod lincov_polish;
mod lincov_selection;
mod visibility;

pub use bound_selection::BoundSelection;
pub use lincov_polish::{GroundLinCovSolution, default_lincov_polish};
pub use lincov_selection::LinCovSelection;

/// Base cost of an infeasible configuration (above every feasible cost).
pub const INFEASIBLE_COST: f64 = 1e4;
/// Cost per radian of elevation below the required minimum.
pub const PENALTY_PER_RAD: f64 = 1e4;
/// Master seed of the truth run behind `optimize orbiters --objective pcrlb`.
pub const PCRLB_SEED: u64 = 1;
/// Truth runs that bound averages over (one: common random numbers for every candidate, so the
/// objective is a smooth function of the elements).
pub const PCRLB_RUNS: usize = 1;

/// Final position PCRLB \[m\] of scenario `cfg` on run 0 of seed [`PCRLB_SEED`] (the bound a
/// `trade --seed 1` reports for its first run): the objective of `optimize orbiters --objective
/// pcrlb`.
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
    /// Time-averaged position PCRLB along the nominal trajectory \[m\] (minimised).
    PcrlbAvg,
    /// Final position PCRLB along the nominal trajectory \[m\] (minimised).
    PcrlbFinal,
    /// `½ (avg/avg_input + final/final_input)` of the nominal position PCRLB (minimised).
    Navigation,
}

impl GroundObjective {
    /// Name used on the command line and in reports: `min-delta`, `logdet`, `min-eig`.
    pub fn name(self) -> &'static str {
        match self {
            GroundObjective::MinDelta { .. } => "min-delta",
            GroundObjective::LogDet => "logdet",
            GroundObjective::MinEig => "min-eig",
            GroundObjective::PcrlbAvg => "pcrlb-avg",
            GroundObjective::PcrlbFinal => "pcrlb-final",
            GroundObjective::Navigation => "nav",
        }
    }

    /// Whether the objective is the nominal position bound (needs
    /// [`GroundProblem::with_reference`] for [`GroundObjective::Navigation`]).
    pub fn is_bound(self) -> bool {
        matches!(
            self,
            GroundObjective::PcrlbAvg | GroundObjective::PcrlbFinal | GroundObjective::Navigation
        )
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
            GroundObjective::PcrlbAvg => {
                "time average of the position PCRLB along the nominal trajectory (dynamics, \
                 prior, every sensor and the ranges to the sites) [m], minimised"
                    .into()
            }
            GroundObjective::PcrlbFinal => {
                "position PCRLB at the last epoch of the nominal trajectory [m], minimised".into()
            }
            GroundObjective::Navigation => {
                "1/2 (pcrlb-avg / input's pcrlb-avg + pcrlb-final / input's pcrlb-final): the \
                 nominal position bound relative to the input design (1 = as good; lower is \
                 better), minimised"
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
    /// The smallest great-circle separation between two sites \[rad\] (`None`: one site).
    pub closest_pair_rad: Option<f64>,
    /// Every site meets the elevation requirement and the minimum separation.
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
    min_separation: f64,
    /// Elevation mask of the placed sites \[rad\] (they measure only above it).
    elevation_mask: f64,
    /// Sites must see the whole entry (eq. 52) — else only some of it above the mask.
    whole_entry: bool,
    /// The nominal bound's beacon-independent part (bound objectives only).
    nominal: Option<NominalBound>,
    /// The input design's (time-averaged, final) nominal bound \[m\].
    reference: Option<(f64, f64)>,
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
        let nominal = if objective.is_bound() {
            Some(NominalBound::new(&scenario)?)
        } else {
            None
        };
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
            min_separation: 0.0,
            elevation_mask: 0.0,
            whole_entry: true,
            nominal,
            reference: None,
        })
    }

    /// Require every two sites to be at least `rad` apart (great circle; 0: no requirement).
    pub fn with_min_separation(mut self, rad: f64) -> Result<GroundProblem, OptimizerError> {
        if !(rad.is_finite() && (0.0..=PI / 2.0).contains(&rad)) {
            return Err(OptimizerError::InvalidInput(format!(
                "minimum separation {} deg must be in [0, 90]",
                rad.to_degrees()
            )));
        }
        self.min_separation = rad;
        Ok(self)
    }

    /// Give the placed sites an elevation mask of `rad` ∈ [0, π/2): in the nominal bound (and in
    /// the scenario written for them) they measure only while the vehicle is above it. It does
    /// not change eq. 52's whole-entry visibility requirement (`min_elevation_rad`).
    pub fn with_elevation_mask(mut self, rad: f64) -> Result<GroundProblem, OptimizerError> {
        if !(rad.is_finite() && (0.0..FRAC_PI_2).contains(&rad)) {
            return Err(OptimizerError::InvalidInput(format!(
                "elevation mask {} deg must be in [0, 90)",
                rad.to_degrees()
            )));
        }
        self.elevation_mask = rad;
        Ok(self)
    }

    /// The elevation mask of the placed sites \[rad\].
    pub fn elevation_mask(&self) -> f64 {
        self.elevation_mask
    }

    /// Drop eq. 52's whole-entry visibility: a site is feasible when it sees some of the
    /// trajectory above its elevation mask, and the search box covers every such site. For the
    /// bound objectives, which count each site's measurements where it has them: a site that
    /// sees only the start or only the end of the entry can be worth more than one that sees all
    /// of it low on the horizon.
    pub fn with_partial_visibility(mut self) -> GroundProblem {
        self.whole_entry = false;
        self
    }

    /// Whether sites must see the whole entry (eq. 52).
    pub fn whole_entry(&self) -> bool {
        self.whole_entry
    }

    /// The input design the [`GroundObjective::Navigation`] value is relative to: its nominal
    /// bound with `sites` (the scenario's own surface beacons, any number; none: the bound of the
    /// other sensors alone) and their elevation mask `mask_rad`.
    pub fn with_reference(
        mut self,
        sites: &[Site],
        mask_rad: f64,
    ) -> Result<GroundProblem, OptimizerError> {
        let series = self.bound_series_masked(sites, mask_rad)?;
        let (avg, last) = (series.time_avg(), series.final_value());
        if !(avg.is_finite() && avg > 0.0 && last.is_finite() && last > 0.0) {
            return Err(OptimizerError::InvalidInput(format!(
                "the input design's position bound ({avg} m averaged, {last} m final) cannot \
                 normalise the navigation objective"
            )));
        }
        self.reference = Some((avg, last));
        Ok(self)
    }

    /// The input design's (time-averaged, final) nominal bound \[m\], when set.
    pub fn reference(&self) -> Option<(f64, f64)> {
        self.reference
    }

    /// The required minimum separation \[rad\].
    pub fn min_separation(&self) -> f64 {
        self.min_separation
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

    /// The working scenario (the base with `count` placeholder surface beacons).
    pub fn scenario(&self) -> &Scenario {
        &self.scenario
    }
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
