//! `entrynav observe`: degree of observability δ(t) along a scenario's trajectory (seed 000 §2.4,
//! seed 002 §3) and the range Fisher information of its beacons (seed 002 §3.2, eq. 54).

use crate::observe_files::{plot, to_json};
use anyhow::{Context, Result, bail};
use clap::Args;
use entrynav::observability::fisher::max_det_bound;
use entrynav::observability::{
    AnalysisPoint, ChannelSet, DegreeSeries, FimEpoch, Method, Scaling, analysis_points,
    degree_series, max_det_directions, range_fim_series,
};
use entrynav::scenario::Scenario;
use entrynav_loader as load;
use serde_json::json;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// Arguments of `entrynav observe`.
#[derive(Args)]
pub struct ObserveArgs {
    /// Built-in scenario name or path to a scenario TOML file.
    #[arg(long)]
    pub scenario: String,
    /// How the observability matrix is computed: `lie` (exact Lie derivatives, seed 002 eq. 12),
    /// `quadratic` (the quadratic approximation, eq. 13-17) or `linear` (the linearisation,
    /// eq. 19).
    #[arg(long, default_value = "lie")]
    pub method: Method,
    /// Also analyse each IMU + one-beacon subsystem (seed 000 eq. 9, Fig. 3).
    #[arg(long)]
    pub subsystems: bool,
    /// Seconds between analysis points along the nominal truth trajectory.
    #[arg(long, default_value_t = 1.0)]
    pub step: f64,
    /// Print the range Fisher information at every point: det, trace, the bounds of seed 002
    /// eq. 27-28 and 37-41, and the geometry index I (eq. 54).
    #[arg(long)]
    pub fim: bool,
    /// With --fim: use only the scenario's first N range beacons, and compare with the best
    /// geometry of N free beacons (seed 002 Table 1, (N/3)^3).
    #[arg(long, value_name = "N")]
    pub beacons: Option<usize>,
    /// Also compute the posterior Cramér–Rao lower bound (the best RMSE any estimator can reach
    /// on the scenario's truth) over `--runs` truth runs, without a filter.
    #[arg(long)]
    pub pcrlb: bool,
    /// With --pcrlb: number of Monte Carlo truth runs the bound averages over.
    #[arg(long, default_value_t = 100, allow_hyphen_values = true, value_parser = crate::args::runs)]
    pub runs: usize,
    /// With --pcrlb: master seed of the truth runs (the runs a `trade` with this seed flies).
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Write the results as JSON to this file.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Write an SVG plot of δ(t) (log axis; and I(t) with --fim) to this file.
    #[arg(long)]
    pub plot: Option<PathBuf>,
}

pub(crate) const RAW_NOTE: &str = "raw SI: delta = sigma_min/sigma_max of O with states in m, rad, m/s, kg/m^3 and outputs in their SI units (the papers' convention)";

/// Run the command.
pub fn run(args: &ObserveArgs) -> Result<()> {
    let method = args.method;
    let (cfg, dir) = load::resolve(&args.scenario, load::Base::CurrentDir)?.into_parts();
    crate::exit::warn_implausible(&cfg);
    let scenario = load::build(cfg, &dir)?;
    let points = analysis_points(&scenario, args.step)?;
    let scaling = Scaling::characteristic(scenario.filter_model());

    let started = Instant::now();
    let central = degree_series(
        &scenario,
        &points,
        &ChannelSet::centralised(&scenario),
        method,
        &scaling,
    )?;
    let central_elapsed = started.elapsed().as_secs_f64();
    let mut subsystems = Vec::new();
    if args.subsystems {
        let sets = ChannelSet::subsystems(&scenario);
        if sets.is_empty() {
            bail!(
                "scenario '{}' has no beacon channels: --subsystems needs range or range-rate \
                 beacons (each subsystem is the IMU plus one beacon)",
                scenario.config.name
            );
        }
        for set in &sets {
            let t0 = Instant::now();
            let s = degree_series(&scenario, &points, set, method, &scaling)?;
            subsystems.push((s, t0.elapsed().as_secs_f64()));
        }
    }
    let fim = if args.fim {
        let subset = match args.beacons {
            Some(n) => Some(first_range_beacons(&scenario, n)?),
            None => None,
        };
        Some(range_fim_series(&scenario, &points, subset.as_deref())?)
    } else {
        None
    };

    print_report(&scenario, &points, &scaling, &central, &subsystems, args);
    if let Some(f) = &fim {
        print_fim(f, args.beacons);
    }
    let pcrlb = if args.pcrlb {
        Some(crate::observe_pcrlb::run(&scenario, args.runs, args.seed)?)
    } else {
        None
    };
    if let Some(path) = &args.json {
        let mut v = to_json(
            &scenario,
            &scaling,
            &central,
            central_elapsed,
            &subsystems,
            fim.as_deref(),
        );
        if let Some(b) = &pcrlb {
            v["pcrlb"] = serde_json::to_value(b)?;
            v["pcrlb_runs"] = json!(args.runs);
            v["pcrlb_seed"] = json!(args.seed);
        }
        entrynav_studies::output::atomic_file::write(
            path,
            serde_json::to_string_pretty(&v)? + "\n",
        )?;
        println!("wrote {}", path.display());
    }
    if let Some(path) = &args.plot {
        create_parent(path)?;
        let subs: Vec<&DegreeSeries> = subsystems.iter().map(|(s, _)| s).collect();
        plot(path, &scenario, &central, &subs, fim.as_deref())?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

/// Indices of the first `n` beacons that have a range channel.
fn first_range_beacons(scenario: &Scenario, n: usize) -> Result<Vec<usize>> {
    let mut ranged: Vec<usize> = scenario
        .channels
        .iter()
        .filter_map(|c| match c.channel {
            entrynav::sensors::Channel::Range(b) => Some(b),
            _ => None,
        })
        .collect();
    ranged.dedup();
    if n == 0 || n > ranged.len() {
        bail!(
            "--beacons {n}: scenario '{}' has {} range beacon(s)",
            scenario.config.name,
            ranged.len()
        );
    }
    ranged.truncate(n);
    Ok(ranged)
}

fn create_parent(path: &Path) -> Result<()> {
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("cannot create {}", parent.display()))?;
    }
    Ok(())
}

fn summary_line(s: &DegreeSeries) -> String {
    let f = |scaled: bool| match s.summary(scaled) {
        Some(m) => format!(
            "{:>10.3e} @{:>6.1} s {:>10.3e} @{:>6.1} s",
            m.min, m.t_min_s, m.max, m.t_max_s
        ),
        None => "(no points)".into(),
    };
    let ranks = |scaled: bool| {
        let r = s
            .samples
            .iter()
            .map(|x| if scaled { x.scaled.rank } else { x.raw.rank });
        let (lo, hi) = r.fold((usize::MAX, 0), |a, v| (a.0.min(v), a.1.max(v)));
        format!("{lo}..{hi}")
    };
    format!(
        "{:<24} {}  {:>6} | {}  {:>6}",
        s.name,
        f(false),
        ranks(false),
        f(true),
        ranks(true)
    )
}

fn print_report(
    scenario: &Scenario,
    points: &[AnalysisPoint],
    scaling: &Scaling,
    central: &DegreeSeries,
    subsystems: &[(DegreeSeries, f64)],
    args: &ObserveArgs,
) {
    let n = scaling.state.len();
    let last = points.last().map_or(0.0, |p| p.t);
    println!("scenario   {}", scenario.config.name);
    println!("states     {n}: {}", scaling.state_names.join(", "));
    println!(
        "method     {} (observability matrix rows: Lie orders 0..{})",
        central.method.name(),
        n - 1
    );
    println!(
        "points     {} (every {} s, t = 0 .. {last} s)",
        points.len(),
        args.step
    );
    println!("RAW        {RAW_NOTE}");
    println!("SCALED     {}", scaling_note(scaling));
    println!("           delta = 0 means numerically rank-deficient (rank < {n}): unobservable");
    println!();
    println!(
        "{:<24} {:<38}  {:>6} | {:<38}  {:>6}",
        "system", "RAW SI delta: min @t, max @t", "rank", "SCALED delta: min @t, max @t", "rank"
    );
    println!("{}", summary_line(central));
    for (s, _) in subsystems {
        println!("{}", summary_line(s));
    }
}

pub(crate) fn scaling_note(scaling: &Scaling) -> String {
    let sizes: Vec<String> = scaling
        .state_names
        .iter()
        .zip(&scaling.state)
        .map(|(n, s)| format!("{n} {s:e}"))
        .collect();
    format!(
        "delta of W*O*D: states divided by characteristic sizes [{}], each row divided by its \
         channel's noise 1-sigma, Lie order k rows times ({} s)^k (dimensionless)",
        sizes.join(", "),
        scaling.time_s
    )
}

/// The lines that summarise the per-epoch FIM table before it: beacons in view, the extremes of
/// det F and of the bound trF^-1 (with their times), the time-averaged geometry index I.
fn fim_summary(fim: &[FimEpoch]) -> Vec<String> {
    let (Some(first), Some(last)) = (fim.first(), fim.last()) else {
        return vec!["summary: no epochs".into()];
    };
    let by = |key: fn(&FimEpoch) -> Option<f64>, max: bool| {
        fim.iter()
            .filter_map(|e| key(e).filter(|v| v.is_finite()).map(|v| (v, e.t)))
            .reduce(|a, b| if (b.0 > a.0) == max { b } else { a })
    };
    let fmt =
        |x: Option<(f64, f64)>| x.map_or("-".to_string(), |(v, t)| format!("{v:.4e} at {t:.1} s"));
    let counts = (
        fim.iter().map(|e| e.summary.count).min().unwrap_or(0),
        fim.iter().map(|e| e.summary.count).max().unwrap_or(0),
    );
    let singular = fim
        .iter()
        .filter(|e| e.summary.trace_inverse.is_none())
        .count();
    let mean_i = fim.iter().map(|e| e.geometry_index).sum::<f64>() / fim.len() as f64;
    vec![
        format!(
            "summary over {} epochs ({:.1} .. {:.1} s): beacons in view {}..{}; F singular (position \
             not determined by the ranges alone) at {singular} epochs",
            fim.len(),
            first.t,
            last.t,
            counts.0,
            counts.1
        ),
        format!(
            "det F min {}, max {}; trF^-1 (bound on tr P) best {}, worst {}; mean I {mean_i:.5}",
            fmt(by(|e| Some(e.summary.det), false)),
            fmt(by(|e| Some(e.summary.det), true)),
            fmt(by(|e| e.summary.trace_inverse, false)),
            fmt(by(|e| e.summary.trace_inverse, true)),
        ),
    ]
}

fn print_fim(fim: &[FimEpoch], beacons: Option<usize>) {
    println!();
    println!(
        "Range Fisher information of the vehicle position ([P2] eq. 36; unit vectors beacon->vehicle)"
    );
    println!(
        "  det F [m^-6], tr F [m^-2]; 3/trF (eq. 28) and trF^-1 (eq. 27) are lower bounds on tr P [m^2];"
    );
    println!("  det<= is eq. 38, detmax is eq. 40 for this many beacons; I is eq. 54");
    for line in fim_summary(fim) {
        println!("  {line}");
    }
    println!(
        "{:>7} {:>3} {:>11} {:>11} {:>11} {:>11} {:>11} {:>11} {:>8}",
        "t [s]", "N", "det F", "tr F", "3/trF", "trF^-1", "det<=", "detmax", "I"
    );
    for e in fim {
        let s = &e.summary;
        let inv = s
            .trace_inverse
            .map_or_else(|| "singular".to_string(), |v| format!("{v:.4e}"));
        println!(
            "{:>7.1} {:>3} {:>11.4e} {:>11.4e} {:>11.4e} {:>11} {:>11.4e} {:>11.4e} {:>8.5}",
            e.t,
            s.count,
            s.det,
            s.trace,
            s.trace_lower_bound,
            inv,
            s.det_upper_bound,
            s.det_max,
            e.geometry_index
        );
    }
    let n = beacons.unwrap_or_else(|| fim.iter().map(|e| e.summary.count).max().unwrap_or(0));
    if n >= 3 {
        let best = max_det_directions(n, 8, 1);
        println!(
            "best geometry of {n} free beacons ([P2] Table 1): max det(sum n n^T) = {:.6} \
             (projected gradient ascent) vs (N/3)^3 = {:.6}; I = det(sum n n^T) for unit sigma, \
             so I <= (N/3)^3",
            best.det,
            max_det_bound(n)
        );
    }
}
