//! The options of the site selection on a candidate grid (`entrynav optimize select`), with their
//! bounds.

use crate::design::check::{CheckSettings, validate_shared};
use crate::design::choices::{Choice, Criterion, SelectObjectiveName};
use crate::design::ground_options::MAX_BEACONS;
use crate::design::ground_options::validate_site_angles;
use crate::error::{StudyError, StudyResult};
use crate::options::{self, OptionError, check_count, check_threads, real};
use std::path::PathBuf;

/// Finest candidate grid \[deg\]: the grid is scanned over the whole visible cap, and at 0.05 deg
/// that is tens of millions of sites each checked along the entry (about a minute); finer grids
/// do not end. The coarsest, 30 deg, is the optimizer's own limit.
pub const MIN_GRID_DEG: f64 = 0.05;
/// Coarsest candidate grid \[deg\].
pub const MAX_GRID_DEG: f64 = 30.0;
/// Most candidates the relaxation is given: its memory and time grow about quadratically with
/// them (475 candidates: 0.06 GB and 0.5 s; 1905: 0.6 GB and 24 s on one core), so 5000 is a few
/// GB and minutes; more is refused before the relaxation, naming a coarser grid or a region.
pub const MAX_CANDIDATES: usize = 5000;
/// Most k-subsets enumerated by the brute force (about a microsecond each: minutes).
pub const MAX_BRUTE_FORCE: usize = 100_000_000;
/// Longest time limit of the branch and bound \[s\] (11.6 days; `Duration` cannot hold much
/// more, and a proof that needs longer belongs to a time limit of its own).
pub const MAX_TIME_LIMIT_S: f64 = 1e6;
/// Largest gap of the branch and bound (ln det and relative λ_min gaps are O(1); one of 1e6
/// accepts any selection).
pub const MAX_GAP: f64 = 1e6;
/// Most nodes per parallel round of the branch and bound: each holds a relaxation in memory,
/// and more than 1024 (the most worker threads) gain nothing.
pub const MAX_BATCH: usize = 1024;
/// Most nodes of the branch and bound (each a relaxation solved in milliseconds to seconds:
/// 10^8 is days; a longer proof belongs to `time_limit`).
pub const MAX_NODES: usize = 100_000_000;

/// The options of a site selection.
#[derive(Debug, Clone, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct SelectOptions {
    /// Number of sites to choose (1 to [`MAX_BEACONS`]; the command line requires it).
    pub k: usize,
    /// Candidate grid spacing in latitude and longitude \[deg\] ([`MIN_GRID_DEG`] to
    /// [`MAX_GRID_DEG`]).
    pub grid_deg: f64,
    /// Criterion certified by the convex relaxation.
    pub criterion: Criterion,
    /// Choose on the nominal position bound instead (no certificate).
    pub objective: Option<SelectObjectiveName>,
    /// Filter whose LinCov the lincov-* objectives score.
    pub lincov_filter: String,
    /// With min-eig: epochs this many seconds apart for the max-min over time.
    pub eig_epochs: Option<f64>,
    /// Seconds between trajectory samples.
    pub step: f64,
    /// Smallest elevation of the vehicle above every candidate's horizon \[deg\].
    pub min_elevation_deg: f64,
    /// Enumerate all k-subsets when there are at most this many (0 to [`MAX_BRUTE_FORCE`]).
    pub brute_force_limit: usize,
    /// Also certify the sites of this `optimize ground` JSON file.
    pub compare: Option<PathBuf>,
    /// Let clarabel print its iteration log of the relaxation (on standard output).
    pub solver_verbose: bool,
    /// Minimum great-circle separation between chosen sites \[deg\] (0: none).
    pub min_separation_deg: f64,
    /// Keep only candidates inside `[lat_min, lat_max, lon_min, lon_max]` \[deg\].
    pub region: Option<Vec<f64>>,
    /// Prove the optimum by branch and bound.
    pub exact: bool,
    /// With `exact`: stop after this many seconds (0 to [`MAX_TIME_LIMIT_S`]).
    pub time_limit: Option<f64>,
    /// With `exact`: stop at this certified gap (0 to [`MAX_GAP`]).
    pub gap: f64,
    /// With `exact`: stop after this many nodes.
    pub node_limit: Option<usize>,
    /// With `exact`: nodes per parallel round (1 to [`MAX_BATCH`]).
    pub batch: usize,
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
    /// The `name` of the scenario the selection is written as (default `selected`; the command
    /// line: the file name of `--write-scenario` without its extension).
    pub scenario_name: Option<String>,
}

impl Default for SelectOptions {
    fn default() -> Self {
        SelectOptions {
            k: 3,
            grid_deg: 0.5,
            criterion: Criterion::Logdet,
            objective: None,
            lincov_filter: "ekf".into(),
            eig_epochs: None,
            step: 1.0,
            min_elevation_deg: 0.0,
            brute_force_limit: 200_000,
            compare: None,
            solver_verbose: false,
            min_separation_deg: 3.0,
            region: None,
            exact: false,
            time_limit: None,
            gap: 1e-6,
            node_limit: None,
            batch: 8,
            threads: None,
            check_runs: 200,
            check_filter: "ekf".into(),
            check_seed: 1,
            no_check: false,
            scenario_name: None,
        }
    }
}

impl SelectOptions {
    /// Refuse an option outside its range or a combination that cannot run, naming it.
    pub fn validate(&self) -> StudyResult<()> {
        check_count("k", self.k, 1, MAX_BEACONS)?;
        real("grid_deg", self.grid_deg, MIN_GRID_DEG, MAX_GRID_DEG)?;
        check_count(
            "brute_force_limit",
            self.brute_force_limit,
            0,
            MAX_BRUTE_FORCE,
        )?;
        if let Some(t) = self.time_limit {
            real("time_limit", t, 0.0, MAX_TIME_LIMIT_S)?;
        }
        real("gap", self.gap, 0.0, MAX_GAP)?;
        check_count("batch", self.batch, 1, MAX_BATCH)?;
        if let Some(n) = self.node_limit {
            check_count("node_limit", n, 1, MAX_NODES)?;
        }
        check_threads(self.threads)?;
        validate_site_angles(self.min_elevation_deg, self.min_separation_deg)?;
        validate_shared(
            &self.lincov_filter,
            (&self.check_filter, self.check_runs, self.no_check),
            self.scenario_name.as_deref(),
        )?;
        self.region_box()?;
        match self.objective {
            Some(o) if self.exact => Err(StudyError::Refused(format!(
                "exact certifies the convex criteria (logdet, min-eig) only; objective {} has \
                 no relaxation bound",
                o.name()
            ))),
            None if self.eig_epochs.is_some() && self.criterion != Criterion::MinEig => Err(
                StudyError::Refused("eig_epochs applies to criterion min-eig only".into()),
            ),
            _ => Ok(()),
        }
    }

    /// Refuse a trajectory step that gives fewer than two samples of the entry (or too many),
    /// and an epoch spacing longer than the entry.
    pub fn validate_steps(&self, duration_s: f64) -> StudyResult<()> {
        options::sample_step("step", self.step, duration_s)?;
        if let Some(e) = self.eig_epochs {
            options::real("eig_epochs", e, options::MIN_SAMPLE_STEP_S, duration_s)?;
        }
        Ok(())
    }

    /// `region` as `[lat_min, lat_max, lon_min, lon_max]` \[deg\], if given: latitudes in
    /// \[-90, 90\], longitudes in \[-360, 360\], each minimum at most its maximum.
    pub fn region_box(&self) -> StudyResult<Option<[f64; 4]>> {
        let Some(v) = self.region.as_deref() else {
            return Ok(None);
        };
        let shown = || {
            v.iter()
                .map(|x| options::number(*x))
                .collect::<Vec<_>>()
                .join(" ")
        };
        let &[lat0, lat1, lon0, lon1] = v else {
            return Err(OptionError::new(
                "region",
                shown(),
                "four numbers LAT_MIN LAT_MAX LON_MIN LON_MAX [deg], e.g. -34 -18 -84 -74",
            )
            .into());
        };
        let lat_ok = |x: f64| (-90.0..=90.0).contains(&x);
        let lon_ok = |x: f64| (-360.0..=360.0).contains(&x);
        if !(lat_ok(lat0) && lat_ok(lat1) && lon_ok(lon0) && lon_ok(lon1))
            || lat0 > lat1
            || lon0 > lon1
        {
            return Err(OptionError::new(
                "region",
                shown(),
                "LAT_MIN <= LAT_MAX in [-90, 90] and LON_MIN <= LON_MAX in [-360, 360] [deg]",
            )
            .into());
        }
        Ok(Some([lat0, lat1, lon0, lon1]))
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
