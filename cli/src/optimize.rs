//! `entrynav optimize`: beacon and orbiter geometry (seed 002 §4) — orbiters on circular orbits,
//! ground beacons visible during the whole entry, and the certified selection of k candidate
//! sites (Joshi & Boyd relaxation).

use crate::load;
use anyhow::{Context, Result, bail};
use clap::{Args, Subcommand};
use entrynav::beacons::BeaconConfig;
use entrynav::observability::{DegreeSeries, Method};
use entrynav::scenario::ScenarioConfig;
use entrynav_optimizer::ground::{self, GroundEvaluation};
use entrynav_optimizer::orbiters::{self, OrbiterEvaluation};
use entrynav_optimizer::output::{self, template_noise};
use entrynav_optimizer::select::{Selection, SelectionReport, site_information};
use entrynav_optimizer::{
    GroundObjective, GroundProblem, OrbitElements, OrbiterObjective, OrbiterProblem, SearchOptions,
    SearchResult, SelectionCriterion, SelectionProblem, Site, Trajectory,
};
use indicatif::{ProgressBar, ProgressStyle};
use serde_json::{Value, json};
use std::path::{Path, PathBuf};
use std::time::Instant;

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
    #[arg(long)]
    pub threads: Option<usize>,
    /// Write the result as JSON to this file.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Write the optimized geometry as a scenario file (accepted by `entrynav trade`).
    #[arg(long)]
    pub write_scenario: Option<PathBuf>,
    /// No progress bar.
    #[arg(long)]
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
    /// Objective: det-n3 (seed 002 eq. 57, 3 orbiters) or logdet (any n >= 3); default det-n3
    /// for 3 orbiters, else logdet.
    #[arg(long, value_parser = ["det-n3", "logdet"])]
    objective: Option<String>,
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
}

/// Arguments of `entrynav optimize ground`.
#[derive(Args)]
pub struct GroundArgs {
    #[command(flatten)]
    common: CommonArgs,
    /// Number of ground beacons (default: the scenario's surface-beacon count, or 3).
    #[arg(long)]
    beacons: Option<usize>,
    /// Objective: min-delta (eq. 49), logdet (integral of ln det FIM) or min-eig (min over time
    /// of lambda_min(FIM)).
    #[arg(long, default_value = "min-delta", value_parser = ["min-delta", "logdet", "min-eig"])]
    objective: String,
    /// Observability method for min-delta (see `entrynav observe`).
    #[arg(long, default_value = "lie", value_parser = ["lie", "quadratic", "linear"])]
    method: String,
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
    /// Write an SVG plot of delta(t) (raw SI, log axis) for the optimum and the scenario's sites.
    #[arg(long)]
    plot: Option<PathBuf>,
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
    /// Criterion: logdet (D-optimal) or min-eig (E-optimal).
    #[arg(long, default_value = "logdet", value_parser = ["logdet", "min-eig"])]
    criterion: String,
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
}

/// Run the command.
pub fn run(args: &OptimizeArgs) -> Result<()> {
    match &args.problem {
        OptimizeProblem::Orbiters(a) => with_threads(a.common.threads, || run_orbiters(a)),
        OptimizeProblem::Ground(a) => with_threads(a.common.threads, || run_ground(a)),
        OptimizeProblem::Select(a) => run_select(a),
    }
}

fn with_threads(threads: Option<usize>, f: impl FnOnce() -> Result<()> + Send) -> Result<()> {
    match threads {
        Some(t) => rayon::ThreadPoolBuilder::new()
            .num_threads(t.max(1))
            .build()?
            .install(f),
        None => f(),
    }
}

fn loader(dir: &Path) -> impl Fn(&str) -> Result<String, String> + use<> {
    let dir = dir.to_path_buf();
    move |p: &str| {
        let path = if Path::new(p).is_absolute() {
            PathBuf::from(p)
        } else {
            dir.join(p)
        };
        std::fs::read_to_string(&path).map_err(|e| format!("cannot read {}: {e}", path.display()))
    }
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
    std::fs::write(path, text).with_context(|| format!("cannot write {}", path.display()))
}

fn write_json(path: &Path, v: &Value) -> Result<()> {
    write_text(path, &(serde_json::to_string_pretty(v)? + "\n"))?;
    println!("wrote {}", path.display());
    Ok(())
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

// ---------------------------------------------------------------------------------------------
// orbiters

/// The scenario's own orbiters on circular orbits: (altitude [m], elements).
fn scenario_orbits(cfg: &ScenarioConfig) -> Vec<(f64, OrbitElements)> {
    cfg.beacons
        .iter()
        .filter_map(|b| match b {
            BeaconConfig::Orbiter(o) => o.circular.map(|c| {
                (
                    c.altitude_km * 1e3,
                    OrbitElements::from_degrees(c.raan_deg, c.inc_deg, c.true_anomaly_deg),
                )
            }),
            BeaconConfig::Surface(_) => None,
        })
        .collect()
}

fn elements_json(el: &[OrbitElements]) -> Value {
    Value::Array(
        el.iter()
            .map(|e| {
                let [raan, inc, f] = e.degrees();
                json!({"raan_deg": raan, "inc_deg": inc, "true_anomaly_deg": f})
            })
            .collect(),
    )
}

fn print_elements(el: &[OrbitElements]) {
    println!(
        "  {:<10} {:>10} {:>10} {:>10}",
        "orbiter", "RAAN [deg]", "i [deg]", "f [deg]"
    );
    for (k, e) in el.iter().enumerate() {
        let [raan, inc, f] = e.degrees();
        println!("  {:<10} {raan:>10.3} {inc:>10.3} {f:>10.3}", k + 1);
    }
}

fn run_orbiters(a: &OrbitersArgs) -> Result<()> {
    let wall = Instant::now();
    let c = &a.common;
    let (cfg, dir) = load::scenario_config(&c.scenario)?;
    let cfg = load::apply_overrides(cfg, &c.sets)?;
    let own = scenario_orbits(&cfg);
    let count = a.orbiters.unwrap_or_else(|| {
        cfg.beacons
            .iter()
            .filter(|b| matches!(b, BeaconConfig::Orbiter(_)))
            .count()
            .max(3)
    });
    let altitude_m = match (a.altitude_km, own.first()) {
        (Some(km), _) => km * 1e3,
        (None, Some((alt, _))) => *alt,
        (None, None) => bail!(
            "scenario '{}' has no circular orbiter to take the altitude from; give --altitude-km",
            cfg.name
        ),
    };
    let objective = a.objective.as_deref().map(|o| match o {
        "det-n3" => OrbiterObjective::DetN3,
        _ => OrbiterObjective::LogDet,
    });
    let scenario = load::build(cfg.clone(), &dir)?;
    let trajectory = Trajectory::from_scenario(&scenario, a.step)?;
    let problem = OrbiterProblem::new(trajectory, count, altitude_m, objective)?;
    let opts = c.search(orbiters::default_search(c.seed));
    let dim = 3 * count;
    let bar = progress_bar(c.quiet, format!("{} orbiters", cfg.name));
    bar.set_length(opts.budget(dim) as u64);
    let progress = |done: usize, total: usize| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    };
    let sol = problem.optimize(&opts, &progress)?;
    bar.finish_and_clear();

    // The scenario's own orbiters (the paper's Table 6 for orbiters-3), when comparable.
    let reference: Option<(Vec<OrbitElements>, OrbiterEvaluation)> = (own.len() == count
        && own.iter().all(|(alt, _)| (alt - altitude_m).abs() < 1e-6))
    .then(|| {
        let el: Vec<OrbitElements> = own.iter().map(|(_, e)| *e).collect();
        problem.evaluate(&el).map(|ev| (el, ev))
    })
    .transpose()?;

    let traj = problem.trajectory();
    let ev = &sol.evaluation;
    println!("scenario    {}", cfg.name);
    println!(
        "problem     {count} orbiters on circular orbits at {:.1} km (seed 002 eq. 55-56), \
         line of sight by eq. 58-60",
        altitude_m / 1e3
    );
    println!(
        "objective   {} = integral over t of {} (trapezoid over {} samples, {:.0} s; \
         upper bound {:.3})",
        problem.objective().name(),
        match problem.objective() {
            OrbiterObjective::DetN3 => "det(N3) = [n1.(n2 x n3)]^2 (eq. 57, 62)",
            OrbiterObjective::LogDet => "ln max(det sum n n^T, 1e-9)",
        },
        traj.len(),
        traj.duration(),
        problem.upper_bound()
    );
    println!();
    println!("optimum     {:.3}", ev.value);
    print_elements(&sol.elements);
    println!(
        "  min visibility margin {:.3} deg, {:.1} % of orbiter-epochs in view",
        ev.min_margin_rad.to_degrees(),
        100.0 * ev.visible_fraction
    );
    if let Some((el, r)) = &reference {
        println!();
        println!(
            "scenario's own orbiters{} evaluated by the same objective: {:.3}",
            if cfg.name == "orbiters-3" {
                " (seed 002 Table 6; paper reports 237.963)"
            } else {
                ""
            },
            r.value
        );
        print_elements(el);
        println!(
            "  min visibility margin {:.3} deg",
            r.min_margin_rad.to_degrees()
        );
    }
    println!();
    println!(
        "search      {} evaluations ({} swarm), {:.3} s search, {:.3} s wall; seed {}, {} starts x {} \
         particles x {} iterations + Nelder-Mead",
        sol.search.evaluations,
        sol.search.swarm_evaluations,
        sol.elapsed_s,
        wall.elapsed().as_secs_f64(),
        opts.seed,
        opts.starts,
        opts.particles,
        opts.iterations
    );

    let noise = template_noise(&cfg, true)?;
    if let Some(path) = &a.export_trajectory {
        let header = [
            ("objective", problem.objective().name().to_string()),
            ("orbiters", count.to_string()),
            ("altitude_m", format!("{altitude_m:e}")),
            (
                "penalty_per_rad_s",
                format!("{:e}", problem.penalty_per_rad_s),
            ),
            ("log_det_floor", format!("{:e}", orbiters::LOG_DET_FLOOR)),
            ("our_value", format!("{:.12e}", ev.value)),
            ("our_search_elapsed_s", format!("{:.6}", sol.elapsed_s)),
        ];
        write_text(path, &traj.to_csv(&header))?;
        println!("wrote {}", path.display());
    }
    if let Some(path) = &c.write_scenario {
        let name = file_stem(path);
        let (_, text) = output::with_beacons(
            &cfg,
            output::orbiter_beacons(&sol.elements, altitude_m, &noise),
            &name,
            &format!(
                "Orbiter geometry optimized by `entrynav optimize orbiters` (seed {}): {} = {:.3}.",
                opts.seed,
                problem.objective().name(),
                ev.value
            ),
        )?;
        write_text(path, &text)?;
        println!("wrote {}", path.display());
    }
    if let Some(path) = &a.plot {
        let t = traj.times.clone();
        let mut curves = vec![crate::plots::Curve {
            name: format!("optimum ({:.3})", ev.value),
            points: t
                .iter()
                .copied()
                .zip(ev.integrand.iter().copied())
                .collect(),
            dashed: false,
        }];
        if let Some((_, r)) = &reference {
            curves.push(crate::plots::Curve {
                name: format!("scenario's orbiters ({:.3})", r.value),
                points: t.iter().copied().zip(r.integrand.iter().copied()).collect(),
                dashed: true,
            });
        }
        write_text(path, "")?;
        crate::plots::line_plot(
            path,
            &format!(
                "{}: {} integrand along the entry",
                cfg.name,
                problem.objective().name()
            ),
            "t [s]",
            match problem.objective() {
                OrbiterObjective::DetN3 => "det(N3)",
                OrbiterObjective::LogDet => "ln det FIM",
            },
            false,
            &curves,
        )?;
        println!("wrote {}", path.display());
    }
    if let Some(path) = &c.json {
        let ev_json = |e: &OrbiterEvaluation| {
            json!({
                "value": e.value,
                "min_visibility_margin_deg": e.min_margin_rad.to_degrees(),
                "visible_fraction": e.visible_fraction,
                "violation_rad_s": e.violation_rad_s,
            })
        };
        let v = json!({
            "problem": "orbiters",
            "scenario": cfg.name,
            "objective": problem.objective().name(),
            "objective_definition": "integral over the trajectory (trapezoid rule) of det(N3) = [n1.(n2 x n3)]^2 (3 orbiters) or ln max(det sum n n^T, 1e-9); n_j unit vector orbiter->vehicle, hidden orbiters (eq. 58-60) contribute nothing",
            "value": ev.value,
            "upper_bound": problem.upper_bound(),
            "orbiters": count,
            "altitude_km": altitude_m / 1e3,
            "elements": elements_json(&sol.elements),
            "min_visibility_margin_deg": ev.min_margin_rad.to_degrees(),
            "visible_fraction": ev.visible_fraction,
            "evaluations": sol.search.evaluations,
            "elapsed_s": sol.elapsed_s,
            "wall_s": wall.elapsed().as_secs_f64(),
            "search": search_json(&sol.search, &opts),
            "trajectory": {
                "samples": traj.len(),
                "step_s": a.step,
                "duration_s": traj.duration(),
                "rule": "trapezoid",
            },
            "reference": reference.as_ref().map(|(el, r)| {
                let mut o = ev_json(r);
                o["elements"] = elements_json(el);
                o["source"] = json!(format!("scenario {} orbiters", cfg.name));
                if cfg.name == "orbiters-3" {
                    o["paper_value"] = json!(237.963);
                }
                o
            }),
        });
        write_json(path, &v)?;
    }
    Ok(())
}

// ---------------------------------------------------------------------------------------------
// ground

/// The scenario's surface beacons as sites (lat/lon/altitude or planet-fixed position).
fn scenario_sites(cfg: &ScenarioConfig) -> Vec<Site> {
    let radius = cfg.planet.resolve().radius;
    cfg.beacons
        .iter()
        .filter_map(|b| match b {
            BeaconConfig::Surface(s) => match (s.lat_deg, s.lon_deg, s.position_km) {
                (Some(lat), Some(lon), _) => Some(Site {
                    altitude_m: s.altitude_km.unwrap_or(0.0) * 1e3,
                    ..Site::from_degrees(lat, lon)
                }),
                (_, _, Some(p)) => {
                    let p = p.map(|c| c * 1e3);
                    let (r, lon, lat) = entrynav::frames::position_to_spherical(&p);
                    Some(Site {
                        lat,
                        lon,
                        altitude_m: r - radius,
                    })
                }
                _ => None,
            },
            BeaconConfig::Orbiter(_) => None,
        })
        .collect()
}

fn sites_json(sites: &[Site]) -> Value {
    Value::Array(
        sites
            .iter()
            .map(|s| {
                let [lat, lon] = s.degrees();
                json!({"lat_deg": lat, "lon_deg": lon})
            })
            .collect(),
    )
}

fn print_sites(sites: &[Site], elevation: Option<&[f64]>) {
    println!(
        "  {:<6} {:>11} {:>11} {:>22}",
        "site", "lat [deg]", "lon [deg]", "min elevation [deg]"
    );
    for (k, s) in sites.iter().enumerate() {
        let [lat, lon] = s.degrees();
        let e = elevation
            .and_then(|e| e.get(k))
            .map_or(String::new(), |e| format!("{:.4}", e.to_degrees()));
        println!("  {:<6} {lat:>11.4} {lon:>11.4} {e:>22}", k + 1);
    }
}

struct DeltaStats {
    raw: DegreeSeries,
}

impl DeltaStats {
    fn min(&self, scaled: bool) -> f64 {
        self.raw.summary(scaled).map_or(0.0, |s| s.min)
    }
    fn max(&self, scaled: bool) -> f64 {
        self.raw.summary(scaled).map_or(0.0, |s| s.max)
    }
    fn json(&self) -> Value {
        let r = self.raw.summary(false);
        let s = self.raw.summary(true);
        json!({
            "method": self.raw.method.name(),
            "delta_raw_min": r.map(|m| m.min),
            "delta_raw_max": r.map(|m| m.max),
            "t_delta_raw_min_s": r.map(|m| m.t_min_s),
            "delta_scaled_min": s.map(|m| m.min),
            "delta_scaled_max": s.map(|m| m.max),
            "times_s": self.raw.times(),
            "delta_raw": self.raw.deltas(false),
            "delta_scaled": self.raw.deltas(true),
        })
    }
}

fn run_ground(a: &GroundArgs) -> Result<()> {
    let wall = Instant::now();
    let c = &a.common;
    let (cfg, dir) = load::scenario_config(&c.scenario)?;
    let cfg = load::apply_overrides(cfg, &c.sets)?;
    let own = scenario_sites(&cfg);
    let count = a
        .beacons
        .unwrap_or(if own.is_empty() { 3 } else { own.len() });
    let method = Method::from_name(&a.method).context("unknown observability method")?;
    let objective = match a.objective.as_str() {
        "min-delta" => GroundObjective::MinDelta {
            method,
            scaled: a.scaled,
        },
        "logdet" => GroundObjective::LogDet,
        _ => GroundObjective::MinEig,
    };
    let load = loader(&dir);
    let min_el = a.min_elevation_deg.to_radians();
    let search_problem = GroundProblem::new(&cfg, &load, count, objective, a.search_step, min_el)?;
    let report = GroundProblem::new(&cfg, &load, count, objective, a.step, min_el)?;
    let opts = c.search(ground::default_search(c.seed));
    let bar = progress_bar(c.quiet, format!("{} ground x{count}", cfg.name));
    let progress = |done: usize, total: usize| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    };
    let sol = search_problem.optimize(&opts, &progress)?;
    bar.finish_and_clear();

    // Report at the fine step: the objective and delta(t) of the optimum and of the scenario's
    // own sites (same count only).
    let ev = report.evaluate(&sol.sites)?;
    let delta = DeltaStats {
        raw: report.delta_series(&sol.sites, method)?,
    };
    let reference: Option<(GroundEvaluation, DeltaStats)> = if own.len() == count {
        let r_ev = report.evaluate(&own)?;
        let d = DeltaStats {
            raw: report.delta_series(&own, method)?,
        };
        Some((r_ev, d))
    } else {
        None
    };
    let paper = cfg.name == "ground-beacons-3";

    println!("scenario    {}", cfg.name);
    println!(
        "problem     {count} ground beacons on the reference sphere, each visible during the whole \
         entry (eq. 52, min elevation {:.3} deg)",
        a.min_elevation_deg
    );
    println!("objective   {}: {}", objective.name(), objective.units());
    println!(
        "            search on samples every {} s, reported every {} s",
        a.search_step, a.step
    );
    println!();
    let fmt_value = |v: Option<f64>| v.map_or("infeasible".to_string(), |v| format!("{v:.6e}"));
    println!("optimum     {} = {}", objective.name(), fmt_value(ev.value));
    print_sites(&sol.sites, Some(&ev.min_elevation_rad));
    println!(
        "  delta ({}) raw SI: min {:.4e}, max {:.4e};  scaled: min {:.4e}, max {:.4e}",
        method.name(),
        delta.min(false),
        delta.max(false),
        delta.min(true),
        delta.max(true)
    );
    if let Some((r, d)) = &reference {
        println!();
        println!(
            "scenario's own sites{}: {} = {}",
            if paper {
                " (hand-placed like seed 002 Fig. 4)"
            } else {
                ""
            },
            objective.name(),
            fmt_value(r.value)
        );
        print_sites(&own, Some(&r.min_elevation_rad));
        println!(
            "  delta ({}) raw SI: min {:.4e}, max {:.4e};  scaled: min {:.4e}, max {:.4e}",
            method.name(),
            d.min(false),
            d.max(false),
            d.min(true),
            d.max(true)
        );
    }
    if paper {
        println!();
        println!(
            "paper (seed 002 Sec. 5.1, its optimum): delta from 1.413e-8 to 2.945e-7 along the \
             entry (raw SI)"
        );
    }
    println!();
    println!(
        "units       raw SI delta: states r [m], lon, lat [rad], v [m/s], fpa, heading [rad], \
         outputs [m], Lie order k rows in m/s^k; scaled: {}",
        scaling_note(&report)
    );
    println!(
        "search      {} evaluations ({} swarm), {:.2} s search, {:.2} s wall; seed {}, {} starts x {} \
         particles x {} iterations + Nelder-Mead",
        sol.search.evaluations,
        sol.search.swarm_evaluations,
        sol.elapsed_s,
        wall.elapsed().as_secs_f64(),
        opts.seed,
        opts.starts,
        opts.particles,
        opts.iterations
    );

    if let Some(path) = &c.write_scenario {
        let name = file_stem(path);
        let (_, text) = output::with_beacons(
            &cfg,
            output::surface_beacons(&sol.sites, &report.noise()),
            &name,
            &format!(
                "Ground sites optimized by `entrynav optimize ground` ({}, seed {}): value {}.",
                objective.name(),
                opts.seed,
                fmt_value(ev.value)
            ),
        )?;
        write_text(path, &text)?;
        println!("wrote {}", path.display());
    }
    if let Some(path) = &a.plot {
        let pts = |d: &DegreeSeries| -> Vec<(f64, f64)> {
            d.times().into_iter().zip(d.deltas(false)).collect()
        };
        let mut curves = vec![crate::plots::Curve {
            name: format!("optimum (min {:.3e})", delta.min(false)),
            points: pts(&delta.raw),
            dashed: false,
        }];
        if let Some((_, d)) = &reference {
            curves.push(crate::plots::Curve {
                name: format!("scenario's sites (min {:.3e})", d.min(false)),
                points: pts(&d.raw),
                dashed: true,
            });
        }
        write_text(path, "")?;
        crate::plots::line_plot(
            path,
            &format!(
                "{}: raw SI δ = σmin/σmax ({}) along the entry",
                cfg.name,
                method.name()
            ),
            "t [s]",
            "δ (raw SI)",
            true,
            &curves,
        )?;
        println!("wrote {}", path.display());
    }
    if let Some(path) = &c.json {
        let v = json!({
            "problem": "ground",
            "scenario": cfg.name,
            "objective": objective.name(),
            "objective_units": objective.units(),
            "value": ev.value,
            "beacons": count,
            "sites": sites_json(&sol.sites),
            "min_elevation_deg": ev.min_elevation_rad.iter().map(|e| e.to_degrees()).collect::<Vec<_>>(),
            "delta": delta.json(),
            "evaluations": sol.search.evaluations,
            "elapsed_s": sol.elapsed_s,
            "wall_s": wall.elapsed().as_secs_f64(),
            "search": search_json(&sol.search, &opts),
            "search_step_s": a.search_step,
            "report_step_s": a.step,
            "delta_units": "raw SI: sigma_min/sigma_max of O with states in m, rad, m/s and outputs in m; scaled: see scaling",
            "scaling": scaling_note(&report),
            "reference": reference.as_ref().map(|(r, d)| json!({
                "source": format!("scenario {} surface beacons", cfg.name),
                "sites": sites_json(&own),
                "value": r.value,
                "min_elevation_deg": r.min_elevation_rad.iter().map(|e| e.to_degrees()).collect::<Vec<_>>(),
                "delta": d.json(),
            })),
            "paper_delta_range": paper.then(|| json!([1.413e-8, 2.945e-7])),
        });
        write_json(path, &v)?;
    }
    Ok(())
}

fn scaling_note(p: &GroundProblem) -> String {
    let s = p.scaling();
    let sizes: Vec<String> = s
        .state_names
        .iter()
        .zip(&s.state)
        .map(|(n, v)| format!("{n} {v:e}"))
        .collect();
    format!(
        "delta of W*O*D with characteristic sizes [{}], rows divided by the range noise 1-sigma, \
         Lie order k rows times ({} s)^k",
        sizes.join(", "),
        s.time_s
    )
}

// ---------------------------------------------------------------------------------------------
// select

fn selection_json(s: &Selection, sites: &[Site], r: &SelectionReport) -> Value {
    let chosen: Vec<Site> = s.indices.iter().map(|&i| sites[i]).collect();
    json!({
        "indices": s.indices,
        "sites": sites_json(&chosen),
        "value": s.value,
        "gap": r.gap(s),
    })
}

fn run_select(a: &SelectArgs) -> Result<()> {
    let wall = Instant::now();
    let (cfg, dir) = load::scenario_config(&a.scenario)?;
    let cfg = load::apply_overrides(cfg, &a.sets)?;
    let load = loader(&dir);
    let criterion = match a.criterion.as_str() {
        "logdet" => SelectionCriterion::LogDet,
        _ => SelectionCriterion::MinEig,
    };
    if a.eig_epochs.is_some() && criterion != SelectionCriterion::MinEig {
        bail!("--eig-epochs applies to --criterion min-eig only");
    }
    let ground = GroundProblem::new(
        &cfg,
        &load,
        a.k.max(1),
        GroundObjective::LogDet,
        a.step,
        a.min_elevation_deg.to_radians(),
    )?;
    let mut sites = ground.visible_grid(a.grid_deg)?;
    let grid_count = sites.len();
    // Heuristic answers to certify: the scenario's own surface sites (if k of them, all
    // feasible) and the sites of a ground-optimizer JSON file.
    let mut extra: Vec<(String, Vec<usize>)> = Vec::new();
    let mut add = |label: String, list: Vec<Site>, sites: &mut Vec<Site>| {
        if list.len() == a.k && list.iter().all(|s| ground.is_feasible(s)) {
            let start = sites.len();
            sites.extend(list);
            extra.push((label, (start..sites.len()).collect()));
        } else {
            println!(
                "note: {label} not certified (needs exactly k = {} sites, each visible during the \
                 whole entry)",
                a.k
            );
        }
    };
    let own = scenario_sites(&cfg);
    if !own.is_empty() {
        add(format!("scenario {} sites", cfg.name), own, &mut sites);
    }
    if let Some(path) = &a.compare {
        let text = std::fs::read_to_string(path)
            .with_context(|| format!("cannot read {}", path.display()))?;
        let v: Value = serde_json::from_str(&text)
            .with_context(|| format!("{} is not JSON", path.display()))?;
        let list = v["sites"]
            .as_array()
            .with_context(|| format!("{} has no \"sites\" array", path.display()))?
            .iter()
            .map(|s| {
                Some(Site::from_degrees(
                    s["lat_deg"].as_f64()?,
                    s["lon_deg"].as_f64()?,
                ))
            })
            .collect::<Option<Vec<Site>>>()
            .with_context(|| format!("{}: sites need lat_deg and lon_deg", path.display()))?;
        add(format!("sites of {}", path.display()), list, &mut sites);
    }
    let blocks = site_information(&ground, &sites, a.eig_epochs)?;
    let problem = SelectionProblem::new(blocks, a.k, criterion)?;
    let report = problem.solve()?;
    let brute = problem.brute_force(a.brute_force_limit);
    let r = &report.relaxation;

    println!("scenario    {}", cfg.name);
    println!(
        "candidates  {grid_count} grid sites every {} deg visible during the whole entry \
         (min elevation {} deg){}",
        a.grid_deg,
        a.min_elevation_deg,
        if sites.len() > grid_count {
            format!(" + {} sites to certify", sites.len() - grid_count)
        } else {
            String::new()
        }
    );
    println!(
        "criterion   {} over k = {} of m = {} ({})",
        criterion.name(),
        a.k,
        sites.len(),
        match (criterion, a.eig_epochs) {
            (SelectionCriterion::LogDet, _) =>
                "ln det of the time-averaged unit-sigma range FIM sum_i A_i, A_i = (1/T) integral n_i n_i^T dt (planet-fixed frame)".to_string(),
            (SelectionCriterion::MinEig, None) =>
                "lambda_min of the time-averaged unit-sigma range FIM".to_string(),
            (SelectionCriterion::MinEig, Some(s)) => format!(
                "min over epochs every {s} s of lambda_min of the instantaneous unit-sigma FIM sum n n^T"
            ),
        }
    );
    println!(
        "relaxation  bound {:.6} (primal {:.6}, dual {:.6}; clarabel {}, {} iterations, {:.3} s)",
        r.bound, r.primal, r.dual, r.status, r.iterations, r.solve_time_s
    );
    let show = |label: &str, s: &Selection| {
        let chosen: Vec<String> = s
            .indices
            .iter()
            .map(|&i| {
                let [lat, lon] = sites[i].degrees();
                format!("({lat:.2}, {lon:.2})")
            })
            .collect();
        println!(
            "{label:<30} value {:>11.6}  gap {:>10.3e}  sites {}",
            s.value,
            report.gap(s),
            chosen.join(" ")
        );
    };
    show("rounded (top-k of z)", &report.rounded);
    show("swap-improved (answer)", &report.improved);
    show("greedy", &report.greedy);
    if let Some(b) = &brute {
        show("brute force (exact optimum)", b);
    }
    let extra_sel: Vec<(String, Selection)> = extra
        .iter()
        .map(|(label, idx)| {
            (
                label.clone(),
                Selection {
                    indices: idx.clone(),
                    value: problem.value(idx),
                },
            )
        })
        .collect();
    for (label, s) in &extra_sel {
        show(label, s);
    }
    println!(
        "            {} criterion evaluations, {:.3} s wall",
        report.evaluations,
        wall.elapsed().as_secs_f64()
    );

    if let Some(path) = &a.write_scenario {
        let noise = template_noise(&cfg, false)?;
        let chosen: Vec<Site> = report.improved.indices.iter().map(|&i| sites[i]).collect();
        let (_, text) = output::with_beacons(
            &cfg,
            output::surface_beacons(&chosen, &noise),
            &file_stem(path),
            &format!(
                "Sites chosen by `entrynav optimize select` ({}, k = {}, grid {} deg): value {:.6}, certified gap {:.3e}.",
                criterion.name(),
                a.k,
                a.grid_deg,
                report.improved.value,
                report.gap(&report.improved)
            ),
        )?;
        write_text(path, &text)?;
        println!("wrote {}", path.display());
    }
    if let Some(path) = &a.json {
        let improved = &report.improved;
        let chosen: Vec<Site> = improved.indices.iter().map(|&i| sites[i]).collect();
        let support: Vec<Value> =
            r.z.iter()
                .enumerate()
                .filter(|(_, z)| **z > 1e-4)
                .map(|(i, z)| {
                    let [lat, lon] = sites[i].degrees();
                    json!({"index": i, "z": z, "lat_deg": lat, "lon_deg": lon})
                })
                .collect();
        let v = json!({
            "problem": "select",
            "scenario": cfg.name,
            "objective": criterion.name(),
            "eig_epochs_s": a.eig_epochs,
            "value": improved.value,
            "sites": sites_json(&chosen),
            "bound": r.bound,
            "gap": report.gap(improved),
            "k": a.k,
            "candidates": sites.len(),
            "grid_candidates": grid_count,
            "grid_deg": a.grid_deg,
            "evaluations": report.evaluations,
            "elapsed_s": report.elapsed_s,
            "wall_s": wall.elapsed().as_secs_f64(),
            "relaxation": {
                "status": r.status,
                "iterations": r.iterations,
                "primal": r.primal,
                "dual": r.dual,
                "solve_time_s": r.solve_time_s,
                "support": support,
            },
            "rounded": selection_json(&report.rounded, &sites, &report),
            "greedy": selection_json(&report.greedy, &sites, &report),
            "brute_force": brute.as_ref().map(|b| selection_json(b, &sites, &report)),
            "certified": extra_sel.iter().map(|(label, s)| {
                let mut o = selection_json(s, &sites, &report);
                o["label"] = json!(label);
                o
            }).collect::<Vec<_>>(),
        });
        write_json(path, &v)?;
    }
    Ok(())
}
