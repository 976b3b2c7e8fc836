//! `entrynav observe`: the command over the observability study (`entrynav_studies::observe`):
//! degree of observability δ(t) along a scenario's trajectory (seed 000 §2.4, seed 002 §3), the
//! range Fisher information of its beacons (seed 002 §3.2, eq. 54) and the PCRLB, printed, and
//! written as JSON and an SVG plot.

use anyhow::{Context, Result};
use clap::Args;
use entrynav::observability::{DegreeSeries, FimEpoch, Method};
use entrynav::scenario::Scenario;
use entrynav_render::observe_figure::observe_figure;
use entrynav_studies::ScenarioInput;
use entrynav_studies::observe::{
    FimSummary, Observation, ObserveOptions, PcrlbBound, RAW_NOTE, run_observe, scaling_note,
};
use std::path::{Path, PathBuf};

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
    #[arg(long, default_value_t = 1, allow_hyphen_values = true, value_parser = crate::args::seed)]
    pub seed: u64,
    /// Write the results as JSON to this file.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Write an SVG plot of δ(t) (log axis; and I(t) with --fim) to this file.
    #[arg(long)]
    pub plot: Option<PathBuf>,
}

/// Run the command.
pub fn run(args: &ObserveArgs) -> Result<()> {
    crate::preflight::check_output_files(&[
        (args.json.as_deref(), "--json"),
        (args.plot.as_deref(), "--plot"),
    ])?;
    let input = ScenarioInput::resolve(&args.scenario, &[])?;
    crate::preflight::warn_implausible(&input.config);
    let scenario = input.build()?;
    let options = ObserveOptions {
        method: args.method,
        subsystems: args.subsystems,
        step: args.step,
        fim: args.fim,
        beacons: args.beacons,
        pcrlb: args.pcrlb,
        runs: args.runs,
        seed: args.seed,
    };
    let study = run_observe(&scenario, &options)?;
    print_report(&scenario, &study);
    if let Some(f) = &study.fim {
        print_fim(f, &study);
    }
    if let Some(b) = &study.pcrlb {
        print_pcrlb(b);
    }
    if let Some(path) = &args.json {
        let v = study.to_json(&scenario);
        entrynav_studies::output::atomic_file::write(
            path,
            serde_json::to_string_pretty(&v)? + "\n",
        )?;
        println!("wrote {}", path.display());
    }
    if let Some(path) = &args.plot {
        create_parent(path)?;
        let subs: Vec<&DegreeSeries> = study.subsystems.iter().map(|(s, _)| s).collect();
        let svg = observe_figure(&scenario, &study.central.0, &subs, study.fim.as_deref())
            .with_context(|| format!("plot {}", path.display()))?;
        entrynav_studies::output::atomic_file::write(path, svg)?;
        println!("wrote {}", path.display());
    }
    Ok(())
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

fn print_report(scenario: &Scenario, study: &Observation) {
    let (points, scaling, central) = (&study.points, &study.scaling, &study.central.0);
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
        study.options.step
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
    for (s, _) in &study.subsystems {
        println!("{}", summary_line(s));
    }
}

/// The lines that summarise the per-epoch FIM table before it: beacons in view, the extremes of
/// det F and of the bound trF^-1 (with their times), the time-averaged geometry index I.
fn fim_summary(fim: &[FimEpoch]) -> Vec<String> {
    let Some(s) = FimSummary::of(fim) else {
        return vec!["summary: no epochs".into()];
    };
    let fmt =
        |x: Option<(f64, f64)>| x.map_or("-".to_string(), |(v, t)| format!("{v:.4e} at {t:.1} s"));
    vec![
        format!(
            "summary over {} epochs ({:.1} .. {:.1} s): beacons in view {}..{}; F singular (position \
             not determined by the ranges alone) at {} epochs",
            s.epochs, s.span_s.0, s.span_s.1, s.in_view.0, s.in_view.1, s.singular
        ),
        format!(
            "det F min {}, max {}; trF^-1 (bound on tr P) best {}, worst {}; mean I {:.5}",
            fmt(s.det.0),
            fmt(s.det.1),
            fmt(s.trace_inverse.0),
            fmt(s.trace_inverse.1),
            s.mean_index
        ),
    ]
}

fn print_fim(fim: &[FimEpoch], study: &Observation) {
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
    if let Some(best) = &study.free_beacons {
        println!(
            "best geometry of {} free beacons ([P2] Table 1): max det(sum n n^T) = {:.6} \
             (projected gradient ascent) vs (N/3)^3 = {:.6}; I = det(sum n n^T) for unit sigma, \
             so I <= (N/3)^3",
            best.n, best.det, best.bound
        );
    }
}

/// The PCRLB's table.
fn print_pcrlb(b: &PcrlbBound) {
    let report = &b.report;
    println!();
    if !report.available {
        println!(
            "PCRLB: not available ({})",
            report.reason.as_deref().unwrap_or("unknown reason")
        );
        return;
    }
    println!(
        "PCRLB over {} truth runs (seed {}, {:.2} s): the lowest RMSE any unbiased estimator can \
         reach on this scenario, in the units of `trade`'s RMSE tables",
        b.runs, b.seed, b.elapsed_s
    );
    println!("  prior: {}", report.prior);
    println!("  {:<14} {:>14} {:>14}", "state", "time-avg", "final");
    for name in &b.names {
        let get =
            |m: &std::collections::BTreeMap<String, Option<f64>>| m.get(name).copied().flatten();
        println!(
            "  {:<14} {:>14} {:>14}",
            name,
            num(get(&report.time_avg)),
            num(get(&report.final_))
        );
    }
}

/// Four significant digits: fixed notation between 1e-3 and 1e6, else `1.234e-5`.
fn num(v: Option<f64>) -> String {
    match v {
        None => "-".into(),
        Some(0.0) => "0".into(),
        Some(v) if (1e-3..1e6).contains(&v.abs()) => {
            let decimals = (3 - v.abs().log10().floor() as i32).max(0) as usize;
            format!("{v:.decimals$}")
        }
        Some(v) => format!("{v:.3e}"),
    }
}
