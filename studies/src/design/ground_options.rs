//! The options of the ground-site design (`entrynav optimize ground`), with their bounds.

use crate::design::check::{CheckSettings, validate_shared};
use crate::design::choices::{DeltaMethod, GroundObjectiveName};
use crate::design::search::SearchCounts;
use crate::error::StudyResult;
use crate::options::{self, check_count, check_threads};
use entrynav_optimizer::ground::default_search;

/// Most ground beacons of a design: a search over 2 × 100 coordinates whose every evaluation
/// scores each site along the whole entry — far more than any entry navigation network (seed 002
/// places 3; the built-in scenarios at most a handful), and a count that no longer sizes an
/// allocation out of reach.
pub const MAX_BEACONS: usize = 100;

/// Highest elevation requirement or mask \[deg\]: a vehicle must be seen above it, so 90 (the
/// zenith alone) leaves no site.
pub const MAX_ELEVATION_DEG: f64 = 89.0;

/// Refuse a site requirement no site can meet, naming it: the vehicle's smallest elevation
/// above every site's horizon (0 to [`MAX_ELEVATION_DEG`]) and the sites' smallest separation
/// (0 to 90 deg).
pub fn validate_site_angles(min_elevation_deg: f64, min_separation_deg: f64) -> StudyResult<()> {
    options::degrees(
        "min_elevation_deg",
        min_elevation_deg,
        0.0,
        MAX_ELEVATION_DEG,
    )?;
    options::degrees("min_separation_deg", min_separation_deg, 0.0, 90.0)?;
    Ok(())
}

/// The options of a ground-site design.
#[derive(Debug, Clone, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct GroundOptions {
    /// Number of ground beacons (default: the scenario's surface-beacon count, or 3); 1 to
    /// [`MAX_BEACONS`].
    pub beacons: Option<usize>,
    /// The objective (default `nav`).
    pub objective: GroundObjectiveName,
    /// Filter whose LinCov the lincov-* objectives score.
    pub lincov_filter: String,
    /// Observability method of δ (min-delta and the reported δ).
    pub method: DeltaMethod,
    /// Maximise the scaled δ instead of the raw-SI one.
    pub scaled: bool,
    /// Seconds between trajectory samples during the search.
    pub search_step: f64,
    /// Seconds between trajectory samples of the reported values.
    pub step: f64,
    /// Smallest elevation of the vehicle above every beacon's horizon during the entry \[deg\].
    pub min_elevation_deg: f64,
    /// Let a site see only part of the entry (above its elevation mask).
    pub partial_visibility: bool,
    /// Smallest great-circle separation between two sites \[deg\].
    pub min_separation_deg: f64,
    /// Elevation mask of the placed sites \[deg\].
    pub elevation_mask_deg: f64,
    /// Seed of the search.
    pub seed: u64,
    /// Independent particle-swarm starts (default 4).
    pub starts: Option<usize>,
    /// Particles per swarm (default 24).
    pub particles: Option<usize>,
    /// Swarm iterations per start (default 60).
    pub iterations: Option<usize>,
    /// Nelder–Mead iterations per polish round (default 150).
    pub polish_iterations: Option<usize>,
    /// Worker threads (`None`: all cores).
    pub threads: Option<usize>,
    /// Monte Carlo runs of the check of each design (10 to 100 000).
    pub check_runs: usize,
    /// Filter flown in the check.
    pub check_filter: String,
    /// Master seed of the check's runs.
    pub check_seed: u64,
    /// Skip the check.
    pub no_check: bool,
    /// The `name` of the scenario the optimum is written as (default `optimized`; the command
    /// line: the file name of `--write-scenario` without its extension).
    pub scenario_name: Option<String>,
}

impl Default for GroundOptions {
    fn default() -> Self {
        GroundOptions {
            beacons: None,
            objective: GroundObjectiveName::Nav,
            lincov_filter: "ekf".into(),
            method: DeltaMethod::Lie,
            scaled: false,
            search_step: 5.0,
            step: 1.0,
            min_elevation_deg: 0.0,
            partial_visibility: false,
            min_separation_deg: 3.0,
            elevation_mask_deg: 0.0,
            seed: 2,
            starts: None,
            particles: None,
            iterations: None,
            polish_iterations: None,
            threads: None,
            check_runs: 200,
            check_filter: "ekf".into(),
            check_seed: 1,
            no_check: false,
            scenario_name: None,
        }
    }
}

impl GroundOptions {
    /// Refuse an option outside its range, naming it (the angles and steps are checked by the
    /// optimizer when it sets the problem up, before the search).
    pub fn validate(&self) -> StudyResult<()> {
        if let Some(n) = self.beacons {
            check_count("beacons", n, 1, MAX_BEACONS)?;
        }
        self.search().validate(default_search(self.seed))?;
        check_threads(self.threads)?;
        validate_site_angles(self.min_elevation_deg, self.min_separation_deg)?;
        options::degrees(
            "elevation_mask_deg",
            self.elevation_mask_deg,
            0.0,
            MAX_ELEVATION_DEG,
        )?;
        validate_shared(
            &self.lincov_filter,
            (&self.check_filter, self.check_runs, self.no_check),
            self.scenario_name.as_deref(),
        )
    }

    /// Refuse a trajectory step that gives fewer than two samples of the entry (or too many).
    pub fn validate_steps(&self, duration_s: f64) -> StudyResult<()> {
        options::sample_step("search_step", self.search_step, duration_s)?;
        options::sample_step("step", self.step, duration_s)?;
        Ok(())
    }

    /// The search's seed and counts.
    pub fn search(&self) -> SearchCounts {
        SearchCounts {
            seed: self.seed,
            starts: self.starts,
            particles: self.particles,
            iterations: self.iterations,
            polish_iterations: self.polish_iterations,
        }
    }

    /// The check's settings (`None` with `no_check`).
    pub fn check(&self) -> Option<CheckSettings<'_>> {
        (!self.no_check).then_some(CheckSettings {
            runs: self.check_runs,
            filter: &self.check_filter,
            seed: self.check_seed,
        })
    }
}
