//! The arguments of `entrynav optimize` and their conversion into the design studies' options
//! (`entrynav_studies::design`): every flag but the output paths is a field of the options.

use crate::args::{QUIET_HELP, ScenarioArgs};
use clap::builder::{PossibleValue, PossibleValuesParser, TypedValueParser};
use clap::{Args, Subcommand};
use entrynav_studies::design::{
    Choice, Criterion, DeltaMethod, GroundObjectiveName, GroundOptions, OrbiterObjectiveName,
    OrbiterOptions, SelectObjectiveName, SelectOptions,
};
use std::path::{Path, PathBuf};

/// A study's named choice on the command line: its names (with their help and aliases) listed
/// and checked by clap, each mapped to its value.
fn choice<T: Choice + Send + Sync>() -> impl TypedValueParser<Value = T> {
    let values = T::ALL.iter().map(|c| {
        PossibleValue::new(c.name())
            .help(c.help())
            .aliases(c.aliases().iter().copied())
    });
    PossibleValuesParser::new(values).map(|name| {
        *T::ALL
            .iter()
            .find(|c| c.name() == name)
            .expect("clap returns a listed name")
    })
}

/// The `name` of a written scenario: `path`'s file name without its extension.
fn stem(path: Option<&Path>) -> Option<String> {
    path.map(|p| {
        p.file_stem()
            .map(|s| s.to_string_lossy().into_owned())
            .unwrap_or_else(|| "optimized".into())
    })
}

/// Arguments of `entrynav optimize`.
#[derive(Args)]
pub struct OptimizeArgs {
    /// Which geometry to optimize.
    #[command(subcommand)]
    pub problem: OptimizeProblem,
}

/// The optimization problems.
#[derive(Subcommand)]
pub enum OptimizeProblem {
    /// Relay orbiters on circular orbits: (RAAN, i, f) per orbiter maximising the integral of
    /// det(N3) (seed 002 eq. 57) or of log det FIM, with line of sight by eq. 58-60.
    Orbiters(OrbitersArgs),
    /// Ground beacons visible during the whole entry (eq. 52): lat/lon maximising min delta
    /// (eq. 49), the integrated log det FIM or the min over time of lambda_min(FIM).
    Ground(GroundArgs),
    /// Choose k of the candidate sites on a lat/lon grid with the convex relaxation (clarabel):
    /// upper bound, rounded + swap-improved selection and certified gaps.
    Select(SelectArgs),
}

/// Options of the check of every optimum against its input design.
#[derive(Args, Clone, Debug)]
pub struct CheckArgs {
    /// Monte Carlo runs of the check of the optimum against the input design (each design; 10
    /// to 100000).
    #[arg(long, default_value_t = 200, allow_hyphen_values = true, value_parser = crate::args::check_runs)]
    pub check_runs: usize,
    /// Filter flown in the check (any the scenario supports).
    #[arg(long, default_value = "ekf")]
    pub check_filter: String,
    /// Master seed of the check's runs (both designs fly the same truths).
    #[arg(long, default_value_t = 1)]
    pub check_seed: u64,
    /// Skip the check (the optimum is then reported unchecked).
    #[arg(long)]
    pub no_check: bool,
}

/// Options shared by the searches.
#[derive(Args, Clone)]
pub struct CommonArgs {
    #[command(flatten)]
    pub scenario: ScenarioArgs,
    /// Seed of the search (the same seed gives the same answer on any thread count).
    #[arg(long, default_value_t = 2, allow_hyphen_values = true, value_parser = crate::args::seed)]
    pub seed: u64,
    /// Independent particle-swarm starts (default: per problem).
    #[arg(long)]
    pub starts: Option<usize>,
    /// Particles per swarm (default: per problem).
    #[arg(long)]
    pub particles: Option<usize>,
    /// Swarm iterations per start (default: per problem).
    #[arg(long)]
    pub iterations: Option<usize>,
    /// Nelder-Mead iterations per polish round (default: per problem).
    #[arg(long)]
    pub polish_iterations: Option<usize>,
    /// The worker pool.
    #[command(flatten)]
    pub workers: crate::args::ThreadsArg,
    /// Write the result as JSON to this file.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Write the optimized geometry as a scenario file (accepted by `entrynav trade`).
    #[arg(long)]
    pub write_scenario: Option<PathBuf>,
    #[arg(long, help = QUIET_HELP)]
    pub quiet: bool,
}

/// Arguments of `entrynav optimize orbiters`.
#[derive(Args)]
pub struct OrbitersArgs {
    #[command(flatten)]
    pub common: CommonArgs,
    /// Number of orbiters (default: the scenario's orbiter count, at least 3).
    #[arg(long)]
    orbiters: Option<usize>,
    /// Orbit altitude above the reference sphere [km] (default: the scenario's first circular
    /// orbiter).
    #[arg(long, allow_negative_numbers = true)]
    altitude_km: Option<f64>,
    /// Objective: nav (both nominal position bounds relative to the scenario's own orbiters;
    /// the default, pcrlb-avg when the scenario has no comparable orbiters), pcrlb-avg,
    /// pcrlb-final; lincov-nav, lincov-avg, lincov-final (the same figures of the filter's
    /// position RMSE predicted by LinCov: the bound's optimum polished on it); or seed 002's
    /// det-n3 (eq. 57, 3 orbiters) and logdet (any n >= 3); pcrlb polishes the geometric
    /// optimum on Monte Carlo run 0's final bound.
    #[arg(long, value_parser = choice::<OrbiterObjectiveName>())]
    objective: Option<OrbiterObjectiveName>,
    /// Filter whose LinCov the lincov-* objectives score (one LinCov can analyse: ekf, or ukf as its EKF equivalent).
    #[arg(long, default_value = "ekf")]
    lincov_filter: String,
    /// Seconds between trajectory samples of the time integral (trapezoid rule).
    #[arg(long, default_value_t = 1.0)]
    step: f64,
    /// Write an SVG plot of the integrand along the trajectory (optimum vs the scenario's own
    /// orbiters).
    #[arg(long)]
    pub plot: Option<PathBuf>,
    /// Export the trajectory and the objective's constants as CSV (for
    /// scripts/bench_orbiters_vs_scipy.py).
    #[arg(long)]
    pub export_trajectory: Option<PathBuf>,
    #[command(flatten)]
    check: CheckArgs,
}

/// Arguments of `entrynav optimize ground`.
#[derive(Args)]
pub struct GroundArgs {
    #[command(flatten)]
    pub common: CommonArgs,
    /// Number of ground beacons (default: the scenario's surface-beacon count, or 3).
    #[arg(long)]
    beacons: Option<usize>,
    /// Objective: nav (both position bounds relative to the input design, the default),
    /// pcrlb-avg, pcrlb-final; lincov-nav, lincov-avg, lincov-final (the same figures of the
    /// filter's position RMSE predicted by LinCov: the bound's optimum polished on it); or seed
    /// 002's min-delta (eq. 49), logdet (integral of ln det FIM), min-eig (min over time of
    /// lambda_min(FIM)).
    #[arg(long, value_parser = choice::<GroundObjectiveName>(), default_value = "nav")]
    objective: GroundObjectiveName,
    /// Filter whose LinCov the lincov-* objectives score (one LinCov can analyse: ekf, or ukf as its EKF equivalent).
    #[arg(long, default_value = "ekf")]
    lincov_filter: String,
    /// Observability method for min-delta (see `entrynav observe`).
    #[arg(long, value_parser = choice::<DeltaMethod>(), default_value = "lie")]
    method: DeltaMethod,
    /// Maximise the scaled delta instead of the raw-SI one (the papers' convention).
    #[arg(long)]
    scaled: bool,
    /// Seconds between trajectory samples during the search.
    #[arg(long, default_value_t = 5.0)]
    search_step: f64,
    /// Seconds between trajectory samples of the reported values and the plot.
    #[arg(long, default_value_t = 1.0)]
    step: f64,
    /// Smallest elevation of the vehicle above every beacon's horizon during the entry [deg]
    /// (eq. 52 is 0).
    #[arg(long, default_value_t = 0.0)]
    min_elevation_deg: f64,
    /// Let a site see only part of the entry (above its elevation mask) instead of all of it
    /// (eq. 52); for the bound objectives, which count each site's measurements where it has
    /// them. Beacons that rise or set during the entry can leave the EKF inconsistent: read the
    /// check.
    #[arg(long, conflicts_with = "min_elevation_deg")]
    partial_visibility: bool,
    /// Smallest great-circle separation between two sites [deg] (0 to 90; default 3: closer
    /// sites see the vehicle along nearly parallel lines, which the bound rewards and a filter
    /// does not survive: two sites 0.5 deg apart gave an EKF ANEES/dof of 26, a certified
    /// selection with sites 2.3 deg apart 8.2; see docs/optimizer.md).
    #[arg(long, default_value_t = 3.0)]
    min_separation_deg: f64,
    /// Elevation mask of the placed sites [deg] (0 to 90): they measure only while the vehicle
    /// is above it, in the bound and in the written scenario (`elevation_mask_deg`). Default 0,
    /// the horizon (eq. 52): on ground-beacons-3 no site sees the whole entry at 6 deg or more, and
    /// with --partial-visibility a 10 deg mask leaves every 3-site design above twice the input's
    /// bound; see docs/optimizer.md.
    #[arg(long, default_value_t = 0.0)]
    elevation_mask_deg: f64,
    /// Write an SVG plot of delta(t) (raw SI, log axis) for the optimum and the scenario's sites.
    #[arg(long)]
    pub plot: Option<PathBuf>,
    #[command(flatten)]
    check: CheckArgs,
}

/// Arguments of `entrynav optimize select`.
#[derive(Args)]
pub struct SelectArgs {
    #[command(flatten)]
    pub scenario: ScenarioArgs,
    /// Number of sites to choose.
    #[arg(long)]
    k: usize,
    /// Candidate grid spacing in latitude and longitude [deg].
    #[arg(long, default_value_t = 0.5)]
    grid_deg: f64,
    /// Criterion: logdet (D-optimal) or min-eig (E-optimal), certified by the convex
    /// relaxation.
    #[arg(long, value_parser = choice::<Criterion>(), default_value = "logdet")]
    criterion: Criterion,
    /// Choose on the nominal position bound instead (nav, pcrlb-avg, pcrlb-final): greedy +
    /// exchanges, a local optimum without certificate (the bound is not concave in the
    /// selection).
    /// lincov-nav, lincov-avg, lincov-final: the bound's selection of the same figure, then
    /// exchanges scored by the filter's LinCov (--lincov-filter).
    #[arg(long, value_parser = choice::<SelectObjectiveName>(), conflicts_with_all = ["criterion", "exact", "eig_epochs"])]
    objective: Option<SelectObjectiveName>,
    /// Filter whose LinCov the lincov-* objectives score (ekf, or ukf as its EKF equivalent).
    #[arg(long, default_value = "ekf")]
    lincov_filter: String,
    /// With min-eig: maximise the minimum over epochs this many seconds apart of lambda_min of
    /// the instantaneous FIM (max-min over time) instead of lambda_min of the time-averaged FIM.
    #[arg(long, value_name = "SECONDS")]
    eig_epochs: Option<f64>,
    /// Seconds between trajectory samples.
    #[arg(long, default_value_t = 1.0)]
    step: f64,
    /// Smallest elevation of the vehicle above every candidate's horizon [deg].
    #[arg(long, default_value_t = 0.0)]
    min_elevation_deg: f64,
    /// Enumerate all k-subsets when there are at most this many.
    #[arg(long, default_value_t = 200_000)]
    brute_force_limit: usize,
    /// Also certify the sites of this `entrynav optimize ground --json` file (added to the
    /// candidates).
    #[arg(long)]
    compare: Option<PathBuf>,
    /// Write the result as JSON to this file.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Write the selected sites as a scenario file (accepted by `entrynav trade`).
    #[arg(long)]
    pub write_scenario: Option<PathBuf>,
    /// Print clarabel's iteration log of the relaxation.
    #[arg(long)]
    solver_verbose: bool,
    /// Minimum great-circle separation between chosen sites [deg] (a linear constraint
    /// z_i + z_j <= 1 of the relaxation for every closer pair; default 3, 0 for none: closer
    /// sites see the vehicle along nearly parallel lines).
    #[arg(long, value_name = "DEG", default_value_t = 3.0)]
    min_separation_deg: f64,
    /// Keep only candidates inside this latitude/longitude box [deg]: four numbers, space- or
    /// comma-separated, e.g. `--region -34 -18 -84 -74` (latitudes -34 to -18, longitudes -84 to
    /// -74) or `--region=-34,-18,-84,-74`.
    #[arg(
        long,
        value_delimiter = ',',
        num_args = 1..=4,
        allow_negative_numbers = true,
        value_names = ["LAT_MIN", "LAT_MAX", "LON_MIN", "LON_MAX"]
    )]
    region: Option<Vec<f64>>,
    /// Prove the optimum: branch and bound on the relaxation (status optimal, gap or time-limit).
    #[arg(long)]
    exact: bool,
    /// With --exact: stop after this many seconds and report the certified gap (the only
    /// speed-dependent output).
    #[arg(long, value_name = "SECONDS", requires = "exact")]
    time_limit: Option<f64>,
    /// With --exact: stop when the certified gap (bound - value) is at most this (logdet:
    /// absolute in ln det, i.e. relative in det; min-eig: relative to lambda_min).
    #[arg(long, default_value_t = 1e-6, requires = "exact")]
    gap: f64,
    /// With --exact: stop after this many nodes (a speed-independent limit).
    #[arg(long, requires = "exact")]
    node_limit: Option<usize>,
    /// With --exact: nodes evaluated per parallel round (the answer depends on it, not on the
    /// thread count).
    #[arg(long, default_value_t = 8, requires = "exact")]
    batch: usize,
    /// The worker pool.
    #[command(flatten)]
    workers: crate::args::ThreadsArg,
    #[arg(long, help = QUIET_HELP)]
    pub quiet: bool,
    #[command(flatten)]
    check: CheckArgs,
}

/// A study's options from arguments named as its options are (the option is the flag with `_`
/// for `-`): `options!(Ty { from a => x, y; from b => z; set field = value; })`.
macro_rules! options {
    ($ty:ident { $(from $src:expr => $($f:ident),+;)+ $(set $name:ident = $value:expr;)* }) => {
        $ty { $($($f: Clone::clone(&$src.$f),)+)+ $($name: $value),* }
    };
}

impl GroundArgs {
    /// The study's options.
    pub fn options(&self) -> GroundOptions {
        let (c, k) = (&self.common, &self.check);
        options!(GroundOptions {
            from self => beacons, objective, lincov_filter, method, scaled, search_step, step,
                min_elevation_deg, partial_visibility, min_separation_deg, elevation_mask_deg;
            from c => seed, starts, particles, iterations, polish_iterations;
            from c.workers => threads;
            from k => check_runs, check_filter, check_seed, no_check;
            set scenario_name = stem(c.write_scenario.as_deref());
        })
    }
}

impl OrbitersArgs {
    /// The study's options.
    pub fn options(&self) -> OrbiterOptions {
        let (c, k) = (&self.common, &self.check);
        options!(OrbiterOptions {
            from self => orbiters, altitude_km, objective, lincov_filter, step;
            from c => seed, starts, particles, iterations, polish_iterations;
            from c.workers => threads;
            from k => check_runs, check_filter, check_seed, no_check;
            set scenario_name = stem(c.write_scenario.as_deref());
        })
    }
}

impl SelectArgs {
    /// The study's options.
    pub fn options(&self) -> SelectOptions {
        options!(SelectOptions {
            from self => k, grid_deg, criterion, objective, lincov_filter, eig_epochs, step,
                min_elevation_deg, brute_force_limit, compare, solver_verbose, min_separation_deg,
                region, exact, time_limit, gap, node_limit, batch;
            from self.workers => threads;
            from self.check => check_runs, check_filter, check_seed, no_check;
            set scenario_name = stem(self.write_scenario.as_deref());
        })
    }
}
