//! [`GroundProblem`]: the ground-beacon problem on one scenario's nominal trajectory (its
//! settings and accessors; the evaluation and search are in `evaluation.rs`), and its default
//! search budget.

use super::objective::GroundObjective;
use super::site::Site;
use crate::error::OptimizerError;
use crate::output::BeaconNoise;
use crate::output::surface_beacons;
use crate::output::template_noise;
use crate::search_options::SearchOptions;
use crate::trajectory::Trajectory;
use entrynav::files::FileLoader;
use entrynav::observability::AnalysisPoint;
use entrynav::observability::ChannelSet;
use entrynav::observability::Scaling;
use entrynav::observability::analysis_points;
use entrynav::scenario::Scenario;
use entrynav::scenario::ScenarioConfig;
use entrynav::sim::bounds::nominal_bound::NominalBound;
use std::f64::consts::{FRAC_PI_2, PI};

/// The ground-beacon problem on one scenario's nominal trajectory.
#[derive(Debug, Clone)]
pub struct GroundProblem {
    pub(super) scenario: Scenario,
    pub(super) points: Vec<AnalysisPoint>,
    pub(super) trajectory: Trajectory,
    pub(super) fixed: Vec<[f64; 3]>,
    pub(super) count: usize,
    pub(super) objective: GroundObjective,
    pub(super) noise: BeaconNoise,
    pub(super) min_elevation: f64,
    pub(super) altitude_m: f64,
    pub(super) scaling: Scaling,
    pub(super) channels: ChannelSet,
    pub(super) min_separation: f64,
    /// Elevation mask of the placed sites \[rad\] (they measure only above it).
    pub(super) elevation_mask: f64,
    /// Sites must see the whole entry (eq. 52) — else only some of it above the mask.
    pub(super) whole_entry: bool,
    /// The nominal bound's beacon-independent part (bound objectives only).
    pub(super) nominal: Option<NominalBound>,
    /// The input design's (time-averaged, final) nominal bound \[m\].
    pub(super) reference: Option<(f64, f64)>,
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
