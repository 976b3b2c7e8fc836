//! `entrynav optimize`: beacon and orbiter geometry (seed 002 §4) — orbiters on circular orbits,
//! ground beacons visible during the whole entry, and the certified selection of k candidate
//! sites (Joshi & Boyd relaxation).
//!
//! This module holds the arguments and the helpers the three problems share; each problem's
//! command is in its own file.

use crate::threads::with_threads;
use anyhow::{Context, Result, bail};
use clap::{Args, Subcommand};
use entrynav::beacons::BeaconConfig;
use entrynav::observability::{DegreeSeries, Method};
use entrynav::scenario::ScenarioConfig;
use entrynav_loader as load;
use entrynav_optimizer::ground::{self, GroundEvaluation};
use entrynav_optimizer::orbiters::{self, OrbiterEvaluation};
use entrynav_optimizer::orbiters_bound::{self, OrbiterBoundProblem};
use entrynav_optimizer::output::{self, template_noise};
use entrynav_optimizer::select::{
    BranchBoundReport, ProofStatus, Selection, separation_constraints, site_information,
};
use entrynav_optimizer::{
    GroundObjective, GroundProblem, OrbitElements, OrbiterObjective, OrbiterProblem, SearchOptions,
    SearchResult, SelectionCriterion, SelectionProblem, Site, Trajectory,
};
use indicatif::{ProgressBar, ProgressStyle};
use names::{CriterionArg, GroundObjectiveArg, MethodArg, OrbiterObjectiveArg};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::time::Instant;

mod bound_selection;
mod design_check;
mod exact_selection;
mod ground_sites;
mod lincov_polish;
mod names;
mod orbit_elements;
mod orbit_files;
mod site_candidates;
mod site_selection;

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

/// Options shared by the searches.
#[derive(Args, Clone)]
pub struct CommonArgs {
    /// Built-in scenario name or path to a scenario TOML file.
    #[arg(long)]
    pub scenario: String,
    /// Override a scenario field: PATH=VALUE in TOML syntax (repeatable).
    #[arg(long = "set", value_name = "PATH=VALUE")]
    pub sets: Vec<String>,
    /// Seed of the search (the same seed gives the same answer on any thread count).
    #[arg(long, default_value_t = 2)]
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
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = crate::args::threads)]
    pub threads: Option<usize>,
    /// Write the result as JSON to this file.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Write the optimized geometry as a scenario file (accepted by `entrynav trade`).
    #[arg(long)]
    pub write_scenario: Option<PathBuf>,
    #[arg(long, help = crate::args::QUIET_HELP)]
    pub quiet: bool,
}

impl CommonArgs {
    fn search(&self, defaults: SearchOptions) -> SearchOptions {
        SearchOptions {
            seed: self.seed,
            starts: self.starts.unwrap_or(defaults.starts),
            particles: self.particles.unwrap_or(defaults.particles),
            iterations: self.iterations.unwrap_or(defaults.iterations),
            polish_iterations: self.polish_iterations.unwrap_or(defaults.polish_iterations),
            polish_step: defaults.polish_step,
        }
    }
}

/// Arguments of `entrynav optimize orbiters`.
#[derive(Args)]
pub struct OrbitersArgs {
    #[command(flatten)]
    common: CommonArgs,
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
    #[arg(long, value_enum)]
    objective: Option<OrbiterObjectiveArg>,
    /// Filter whose LinCov the lincov-* objectives score (one LinCov can analyse: ekf, or ukf as its EKF equivalent).
    #[arg(long, default_value = "ekf")]
    lincov_filter: String,
    /// Seconds between trajectory samples of the time integral (trapezoid rule).
    #[arg(long, default_value_t = 1.0)]
    step: f64,
    /// Write an SVG plot of the integrand along the trajectory (optimum vs the scenario's own
    /// orbiters).
    #[arg(long)]
    plot: Option<PathBuf>,
    /// Export the trajectory and the objective's constants as CSV (for
    /// scripts/bench_orbiters_vs_scipy.py).
    #[arg(long)]
    export_trajectory: Option<PathBuf>,
    #[command(flatten)]
    check: design_check::CheckArgs,
}

/// Arguments of `entrynav optimize ground`.
#[derive(Args)]
pub struct GroundArgs {
    #[command(flatten)]
    common: CommonArgs,
    /// Number of ground beacons (default: the scenario's surface-beacon count, or 3).
    #[arg(long)]
    beacons: Option<usize>,
    /// Objective: nav (both position bounds relative to the input design, the default),
    /// pcrlb-avg, pcrlb-final; lincov-nav, lincov-avg, lincov-final (the same figures of the
    /// filter's position RMSE predicted by LinCov: the bound's optimum polished on it); or seed
    /// 002's min-delta (eq. 49), logdet (integral of ln det FIM), min-eig (min over time of
    /// lambda_min(FIM)).
    #[arg(long, value_enum, default_value_t = GroundObjectiveArg::Nav)]
    objective: GroundObjectiveArg,
    /// Filter whose LinCov the lincov-* objectives score (one LinCov can analyse: ekf, or ukf as its EKF equivalent).
    #[arg(long, default_value = "ekf")]
    lincov_filter: String,
    /// Observability method for min-delta (see `entrynav observe`).
    #[arg(long, value_enum, default_value_t = MethodArg::Lie)]
    method: MethodArg,
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
    plot: Option<PathBuf>,
    #[command(flatten)]
    check: design_check::CheckArgs,
}

/// Arguments of `entrynav optimize select`.
#[derive(Args)]
pub struct SelectArgs {
    /// Built-in scenario name or path to a scenario TOML file.
    #[arg(long)]
    scenario: String,
    /// Override a scenario field: PATH=VALUE in TOML syntax (repeatable).
    #[arg(long = "set", value_name = "PATH=VALUE")]
    sets: Vec<String>,
    /// Number of sites to choose.
    #[arg(long)]
    k: usize,
    /// Candidate grid spacing in latitude and longitude [deg].
    #[arg(long, default_value_t = 0.5)]
    grid_deg: f64,
    /// Criterion: logdet (D-optimal) or min-eig (E-optimal), certified by the convex
    /// relaxation.
    #[arg(long, value_enum, default_value_t = CriterionArg::Logdet)]
    criterion: CriterionArg,
    /// Choose on the nominal position bound instead (nav, pcrlb-avg, pcrlb-final): greedy +
    /// exchanges, a local optimum without certificate (the bound is not concave in the
    /// selection).
    /// lincov-nav, lincov-avg, lincov-final: the bound's selection of the same figure, then
    /// exchanges scored by the filter's LinCov (--lincov-filter).
    #[arg(long, value_enum, conflicts_with_all = ["criterion", "exact", "eig_epochs"])]
    objective: Option<names::SelectObjectiveArg>,
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
    json: Option<PathBuf>,
    /// Write the selected sites as a scenario file (accepted by `entrynav trade`).
    #[arg(long)]
    write_scenario: Option<PathBuf>,
    /// Print clarabel's iteration log of the relaxation.
    #[arg(long)]
    solver_verbose: bool,
    /// Minimum great-circle separation between chosen sites [deg] (a linear constraint
    /// z_i + z_j <= 1 of the relaxation for every closer pair; default 3, 0 for none: closer
    /// sites see the vehicle along nearly parallel lines).
    #[arg(long, value_name = "DEG", default_value_t = 3.0)]
    min_separation_deg: f64,
    /// Keep only candidates inside this latitude/longitude box [deg].
    #[arg(
        long,
        value_delimiter = ',',
        num_args = 1,
        allow_hyphen_values = true,
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
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = crate::args::threads)]
    threads: Option<usize>,
    #[arg(long, help = crate::args::QUIET_HELP)]
    quiet: bool,
    #[command(flatten)]
    check: design_check::CheckArgs,
}

/// Run the command.
pub fn run(args: &OptimizeArgs) -> Result<()> {
    match &args.problem {
        OptimizeProblem::Orbiters(a) => {
            with_threads(a.common.threads, || orbit_elements::run_orbiters(a))
        }
        OptimizeProblem::Ground(a) => {
            with_threads(a.common.threads, || ground_sites::run_ground(a))
        }
        OptimizeProblem::Select(a) => with_threads(a.threads, || match a.objective {
            Some(o) => bound_selection::run_select_on_bound(a, o),
            None => site_selection::run_select(a),
        }),
    }
}

fn loader(dir: &Path) -> impl Fn(&str) -> Result<String, entrynav::files::FileError> + use<> {
    load::file_loader(dir)
}

fn progress_bar(quiet: bool, label: String) -> ProgressBar {
    let bar = if quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(1)
    };
    bar.set_style(
        ProgressStyle::with_template("{spinner} {msg} [{bar:40}] {pos}/{len} evaluations ({eta})")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    bar.set_message(label);
    bar
}

fn write_text(path: &Path, text: &str) -> Result<()> {
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("cannot create {}", parent.display()))?;
    }
    Ok(entrynav_studies::output::atomic_file::write(path, text)?)
}

fn write_json(path: &Path, v: &Value) -> Result<()> {
    write_text(path, &(serde_json::to_string_pretty(v)? + "\n"))?;
    println!("wrote {}", path.display());
    Ok(())
}

/// The `search` summary line of `optimize orbiters` and `optimize ground`.
fn print_search(s: &SearchResult, search_s: f64, wall: Instant, opts: &SearchOptions) {
    println!(
        "search      {} evaluations ({} swarm), {:.3} s search, {:.3} s wall; seed {}, {} starts x {} \
         particles x {} iterations + Nelder-Mead",
        s.evaluations,
        s.swarm_evaluations,
        search_s,
        wall.elapsed().as_secs_f64(),
        opts.seed,
        opts.starts,
        opts.particles,
        opts.iterations
    );
}

fn search_json(s: &SearchResult, opts: &SearchOptions) -> Value {
    json!({
        "seed": opts.seed,
        "starts": opts.starts,
        "particles": opts.particles,
        "iterations": opts.iterations,
        "polish_iterations": opts.polish_iterations,
        "swarm_evaluations": s.swarm_evaluations,
        "start_costs": s.start_costs,
        "best_start": s.best_start,
    })
}

fn file_stem(path: &Path) -> String {
    path.file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "optimized".into())
}
