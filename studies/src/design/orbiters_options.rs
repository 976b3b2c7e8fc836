//! The options of the orbiter design (`entrynav optimize orbiters`), with their bounds.

use crate::design::check::{CheckSettings, validate_shared};
use crate::design::choices::OrbiterObjectiveName;
use crate::design::search::SearchCounts;
use crate::error::StudyResult;
use crate::options::{self, check_count, check_threads};
use entrynav_optimizer::orbiters::default_search;

/// Most orbiters of a design: a search over 3 × 100 elements, each evaluation propagating every
/// orbiter along the entry — far beyond any relay constellation (seed 002 flies 3), and a count
/// that no longer sizes an allocation out of reach. Fewer than 3 are refused by the problem
/// itself, which says why (the position FIM is singular).
pub const MAX_ORBITERS: usize = 100;

/// Lowest circular-orbit altitude \[km\]: below about 80 km the orbit is inside the atmosphere
/// the vehicle enters.
pub const MIN_ALTITUDE_KM: f64 = 80.0;
/// Highest circular-orbit altitude \[km\]: 100 000 km is four times Deimos' orbit and still
/// well inside Mars' sphere of influence (about 577 000 km).
pub const MAX_ALTITUDE_KM: f64 = 100_000.0;

/// The options of an orbiter design.
#[derive(Debug, Clone, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct OrbiterOptions {
    /// Number of orbiters (default: the scenario's orbiter count, at least 3); 1 to
    /// [`MAX_ORBITERS`].
    pub orbiters: Option<usize>,
    /// Orbit altitude above the reference sphere \[km\] (default: the scenario's first circular
    /// orbiter).
    pub altitude_km: Option<f64>,
    /// The objective (default: `nav`, or `pcrlb-avg` when the scenario has no comparable
    /// orbiters).
    pub objective: Option<OrbiterObjectiveName>,
    /// Filter whose LinCov the lincov-* objectives score.
    pub lincov_filter: String,
    /// Seconds between trajectory samples of the time integral.
    pub step: f64,
    /// Seed of the search.
    pub seed: u64,
    /// Independent particle-swarm starts (default 8).
    pub starts: Option<usize>,
    /// Particles per swarm (default 40).
    pub particles: Option<usize>,
    /// Swarm iterations per start (default 150).
    pub iterations: Option<usize>,
    /// Nelder–Mead iterations per polish round (default 600).
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

impl Default for OrbiterOptions {
    fn default() -> Self {
        OrbiterOptions {
            orbiters: None,
            altitude_km: None,
            objective: None,
            lincov_filter: "ekf".into(),
            step: 1.0,
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

impl OrbiterOptions {
    /// Refuse an option outside its range, naming it (the altitude and the step are checked by
    /// the optimizer when it sets the problem up, before the search).
    pub fn validate(&self) -> StudyResult<()> {
        if let Some(n) = self.orbiters {
            check_count("orbiters", n, 1, MAX_ORBITERS)?;
        }
        self.search().validate(default_search(self.seed))?;
        check_threads(self.threads)?;
        if let Some(h) = self.altitude_km {
            options::real("altitude_km", h, MIN_ALTITUDE_KM, MAX_ALTITUDE_KM)?;
        }
        validate_shared(
            &self.lincov_filter,
            (&self.check_filter, self.check_runs, self.no_check),
            self.scenario_name.as_deref(),
        )
    }

    /// Refuse a trajectory step that gives fewer than two samples of the entry (or too many).
    pub fn validate_steps(&self, duration_s: f64) -> StudyResult<()> {
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
