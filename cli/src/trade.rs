//! `entrynav trade`: Monte Carlo comparison of navigation filters on a scenario.

use crate::atmosphere_file::{check_profile_covers, report_truth_table, truth_atmosphere};
use crate::exit::{check_output_dir, check_output_file, is_stdout};
use crate::provenance::{Provenance, Summary, Timing};
use anyhow::{Context, Result};
use clap::Args;
use entrynav::estimation::nav::FilterKind;
use entrynav::sim::shard::fold_partial;
use entrynav::sim::{
    FilterReport, McOptions, Shard, ShardResult, TradeReport, merge_shards, resume_shard, run_shard,
};
use entrynav_loader as load;
use indicatif::{ProgressBar, ProgressStyle};
use std::io::Write;
use std::path::{Path, PathBuf};

/// Arguments of `entrynav trade`.
#[derive(Args)]
#[command(args_conflicts_with_subcommands = true, subcommand_negates_reqs = true)]
pub struct TradeArgs {
    /// Merge shard files or compare summaries instead of running.
    #[command(subcommand)]
    pub action: Option<TradeAction>,
    /// Built-in scenario name or path to a scenario TOML file.
    #[arg(long, required_unless_present = "grid")]
    pub scenario: Option<String>,
    /// Override a scenario field: PATH=VALUE in TOML syntax (repeatable), e.g.
    /// `--set truth.density_bias=0.095`.
    #[arg(long = "set", value_name = "PATH=VALUE")]
    pub sets: Vec<String>,
    /// Comma-separated filters: ekf, ukf, ci, dcifaif, mmae, mmae-moe, ukf-cm, ukf-ac, uskf-nn.
    #[arg(long, default_value = "ekf")]
    pub filters: String,
    /// Monte Carlo runs (default: the scenario's monte_carlo.runs).
    #[arg(long)]
    pub runs: Option<usize>,
    /// Master seed; the same seed gives the same statistics on any thread count.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = crate::exit::parse_threads)]
    pub threads: Option<usize>,
    /// Write the summary as JSON (`-`: to standard output, and no tables). Every output path is
    /// checked before the first run.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Write per-filter time series (RMSE, mean σ, NEES, …) as CSV files into this directory.
    #[arg(long)]
    pub csv_dir: Option<PathBuf>,
    /// Write SVG plots (RMSE vs time, errors with 3σ envelopes, NEES) into this directory.
    #[arg(long)]
    pub plots: Option<PathBuf>,
    /// Write one self-contained HTML report (inline SVG and CSS, nothing from the network):
    /// consistency verdicts, RMSE and PCRLB, errors with ±3σ, NEES/NIS, weights, dispersion,
    /// provenance. With --grid, the grid's report. Checked before the first run.
    #[arg(long, value_name = "FILE.html")]
    pub report: Option<PathBuf>,
    #[arg(long, help = crate::QUIET_HELP)]
    pub quiet: bool,
    /// The truth atmosphere file and how to read it.
    #[command(flatten)]
    pub atmosphere: crate::atmosphere_file::AtmosphereFileArgs,
    /// Fly every run in the unperturbed truth mean atmosphere (no per-run perturbation).
    #[arg(long)]
    pub no_perturbation: bool,
    /// Run a grid of scenarios × variations × filters (see `docs/tutorial.md`); the report
    /// (Markdown, CSV, JSON, SVG plots) goes to --out-dir.
    #[arg(long, value_name = "FILE.toml", conflicts_with_all = ["shard"])]
    pub grid: Option<PathBuf>,
    /// Output directory of a --grid report.
    #[arg(long, default_value = "out/grid")]
    pub out_dir: PathBuf,
    /// Run only shard I of N (contiguous blocks of runs) and write the shard file to --json;
    /// `entrynav trade merge` combines the shards into exactly the single-process result.
    #[arg(long, value_name = "I/N")]
    pub shard: Option<String>,
    /// Replay run K of this study (same scenario, --set overrides, seed and filters) and write
    /// its full series per filter to --csv-dir: truth, estimate, σ, error, NEES, innovation and
    /// NIS per channel, weights. Use it on a run listed under `failures`.
    #[arg(long, value_name = "K", requires = "csv_dir", conflicts_with_all = ["shard", "grid"])]
    pub replay_run: Option<usize>,
    /// Continue the interrupted study whose partial summary (`complete: false`) is FILE: give
    /// the same scenario, overrides, filters, runs and seed; the result is exactly that of an
    /// uninterrupted run.
    #[arg(long, value_name = "FILE", conflicts_with_all = ["shard", "grid", "replay_run"])]
    pub resume: Option<PathBuf>,
    /// Skip the posterior Cramér–Rao lower bound (on by default: the `pcrlb` block of the
    /// summary, each filter's RMSE/PCRLB efficiency, the dashed PCRLB curve in the RMSE plots;
    /// it costs about one EKF's worth of work per run).
    #[arg(long)]
    pub no_pcrlb: bool,
}

/// `entrynav trade merge`, `entrynav trade compare`.
#[derive(clap::Subcommand)]
pub enum TradeAction {
    /// Compare two trade summaries (`trade --json`): per filter in both, B − A of every RMSE and
    /// ANEES with a 95 % Monte Carlo interval; refuses different scenarios.
    Compare(crate::compare::CompareArgs),
    /// Combine shard files written by `trade --shard I/N --json FILE` into the study's report.
    Merge {
        /// Shard files (all N shards of one study).
        #[arg(required = true)]
        shards: Vec<PathBuf>,
        /// Write the merged summary as JSON.
        #[arg(long)]
        json: Option<PathBuf>,
        /// Write per-filter time series as CSV into this directory.
        #[arg(long)]
        csv_dir: Option<PathBuf>,
        /// Write SVG plots into this directory.
        #[arg(long)]
        plots: Option<PathBuf>,
    },
}

/// Run the command.
pub fn run(args: &TradeArgs) -> Result<()> {
    if let Some(TradeAction::Compare(c)) = &args.action {
        return crate::compare::run(c);
    }
    if let Some(TradeAction::Merge {
        shards,
        json,
        csv_dir,
        plots,
    }) = &args.action
    {
        return merge(
            shards,
            json.as_deref(),
            csv_dir.as_deref(),
            plots.as_deref(),
        );
    }
    if let Some(grid) = &args.grid {
        check_output_dir(&args.out_dir, "--out-dir")?;
        crate::report::check_path(args.report.as_deref())?;
        return crate::grid::run(grid, &args.out_dir, args.quiet, args.report.as_deref());
    }
    check_outputs(
        args.json.as_deref(),
        args.csv_dir.as_deref(),
        args.plots.as_deref(),
    )?;
    crate::report::check_path(args.report.as_deref())?;
    let to_stdout = args.json.as_deref().is_some_and(is_stdout);
    let scenario_name = args.scenario.as_deref().context("--scenario is required")?;
    let (cfg, dir) = load::resolve(scenario_name, load::Base::CurrentDir)?.into_parts();
    let cfg = load::apply_overrides(cfg, &args.sets)?;
    let cfg = truth_atmosphere(cfg, &args.atmosphere, args.no_perturbation)?;
    let scenario = load::build(cfg, &dir)?;
    report_truth_table(&scenario);
    if let Some(file) = &args.atmosphere.atmosphere_file {
        check_profile_covers(&scenario, file)?;
    }
    let filters = FilterKind::parse_list(&args.filters, &scenario.onboard)?;
    let runs = args.runs.unwrap_or(scenario.config.monte_carlo.runs);
    if let (Some(k), Some(dir)) = (args.replay_run, &args.csv_dir) {
        return crate::replay::write_replay(&scenario, &filters, args.seed, k, dir);
    }
    let previous = args.resume.as_deref().map(read_resume).transpose()?;
    let opts = McOptions {
        pcrlb: !args.no_pcrlb,
        cancel: Some(crate::interrupt::install()),
        ..McOptions::new(runs, args.seed)
    };
    if let Some(spec) = &args.shard {
        let shard = Shard::parse(spec)?;
        let path = args
            .json
            .as_ref()
            .context("--shard needs --json FILE to write the shard to")?;
        let result = run_shard(&scenario, &filters, &opts, shard, &|_| {})?;
        if !result.complete {
            return Err(crate::interrupt::Interrupted(format!(
                "shard {}/{} not written (a shard must be complete to merge)",
                shard.index, shard.count
            ))
            .into());
        }
        write_file(path, |w| Ok(serde_json::to_writer(&mut *w, &result)?))?;
        let n: usize = result.blocks.len();
        eprintln!(
            "wrote shard {}/{} ({n} blocks) of {} runs to {}",
            shard.index,
            shard.count,
            runs,
            path.display()
        );
        return Ok(());
    }
    let bar = if args.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(runs as u64)
    };
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} {msg} [{bar:40}] {pos}/{len} runs ({per_sec}, eta {eta})",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> "),
    );
    bar.set_message(format!("{} × {}", scenario.config.name, args.filters));
    let clock = std::time::Instant::now();
    let study = {
        let progress = |done: usize| bar.set_position(done as u64);
        let run = || match previous {
            Some(prev) => resume_shard(&scenario, &filters, &opts, prev, &progress),
            None => run_shard(
                &scenario,
                &filters,
                &opts,
                Shard { index: 0, count: 1 },
                &progress,
            ),
        };
        match args.threads {
            Some(t) => rayon::ThreadPoolBuilder::new()
                .num_threads(t.max(1))
                .build()?
                .install(run)?,
            None => run()?,
        }
    };
    // A partial study keeps its block sums in the summary, for --resume.
    let (report, resume) = if study.complete {
        (merge_shards(vec![study])?, None)
    } else {
        (fold_partial(study.clone())?, Some(study))
    };
    bar.finish_and_clear();
    let elapsed = clock.elapsed().as_secs_f64();
    if !report.complete {
        eprintln!(
            "interrupted: {} of {} runs completed; writing the partial results",
            report.runs_completed, report.runs
        );
    }
    // With `--json -` the JSON is standard output: no tables, notes to stderr.
    let note = |msg: String| {
        if to_stdout {
            eprintln!("{msg}");
        } else {
            println!("{msg}");
        }
    };
    if !to_stdout {
        print_tables(&report, elapsed);
    }
    if let Some(path) = &args.json {
        let provenance = Provenance::new(&args.sets)
            .with_scenario(&scenario, args.atmosphere.atmosphere_file.as_deref());
        write_summary(path, &provenance, &report, resume.as_ref(), elapsed)?;
        if !to_stdout {
            note(format!("wrote {}", path.display()));
        }
    }
    if let Some(dir) = &args.csv_dir {
        write_csv_dir(dir, &report)?;
        note(format!("wrote CSV series to {}", dir.display()));
    }
    let names = crate::plot::labels::WeightNames::of_scenario(&scenario);
    if let Some(dir) = &args.plots {
        crate::plots::trade_plots(dir, &report, &names)?;
        note(format!("wrote plots to {}", dir.display()));
    }
    if let Some(path) = &args.report {
        let provenance = Provenance::new(&args.sets)
            .with_scenario(&scenario, args.atmosphere.atmosphere_file.as_deref());
        let s = crate::report::write_trade(path, &report, &names, &provenance, elapsed)?;
        note(format!("wrote report {} in {s:.3} s", path.display()));
    }
    if !report.complete {
        return Err(crate::interrupt::Interrupted(format!(
            "{} of {} runs completed (complete: false in the summary)",
            report.runs_completed, report.runs
        ))
        .into());
    }
    Ok(())
}

fn merge(
    shards: &[PathBuf],
    json: Option<&Path>,
    csv_dir: Option<&Path>,
    plots: Option<&Path>,
) -> Result<()> {
    check_outputs(json, csv_dir, plots)?;
    let mut parts = Vec::new();
    for p in shards {
        let text = std::fs::read_to_string(p)
            .with_context(|| format!("cannot read shard {}", p.display()))?;
        let part: ShardResult = serde_json::from_str(&text)
            .with_context(|| format!("{} is not a shard file", p.display()))?;
        parts.push(part);
    }
    let fingerprint = parts
        .first()
        .map(|p| p.scenario_fingerprint.clone())
        .unwrap_or_default();
    let report = merge_shards(parts)?;
    if !json.is_some_and(is_stdout) {
        print_tables(&report, 0.0);
    }
    if let Some(path) = json {
        let provenance = Provenance {
            scenario_fingerprint: Some(fingerprint),
            ..Provenance::new(&[])
        };
        write_summary(path, &provenance, &report, None, 0.0)?;
        println!("wrote {}", path.display());
    }
    if let Some(dir) = csv_dir {
        write_csv_dir(dir, &report)?;
    }
    let names = crate::plot::labels::WeightNames::of_channels(&report.channels);
    if let Some(dir) = plots {
        crate::plots::trade_plots(dir, &report, &names)?;
    }
    Ok(())
}

/// Write a trade summary: provenance, the statistics, then the wall-clock `timing`.
fn write_summary(
    path: &Path,
    provenance: &Provenance,
    report: &TradeReport,
    resume: Option<&ShardResult>,
    wall_s: f64,
) -> Result<()> {
    let summary = Summary {
        provenance,
        report,
        resume,
        timing: Timing::of(report, wall_s),
    };
    write_file(path, |w| {
        serde_json::to_writer_pretty(&mut *w, &summary)?;
        writeln!(w)?;
        Ok(())
    })
}

/// The block sums stored in the partial summary `path` (`--resume`).
fn read_resume(path: &Path) -> Result<ShardResult> {
    let usage = |m: String| crate::exit::Usage(format!("--resume {}: {m}", path.display()));
    let text = std::fs::read_to_string(path).map_err(|e| usage(e.to_string()))?;
    let mut v: serde_json::Value =
        serde_json::from_str(&text).map_err(|e| usage(format!("not JSON: {e}")))?;
    let block = v
        .get_mut("resume")
        .map(serde_json::Value::take)
        .ok_or_else(|| {
            usage("no `resume` block: not the summary of an interrupted trade".into())
        })?;
    Ok(serde_json::from_value(block).map_err(|e| usage(format!("corrupt `resume` block: {e}")))?)
}

/// Check every output path of a study before its first run (exit code 2 naming the path).
fn check_outputs(json: Option<&Path>, csv_dir: Option<&Path>, plots: Option<&Path>) -> Result<()> {
    if let Some(p) = json {
        check_output_file(p, "--json")?;
    }
    if let Some(d) = csv_dir {
        check_output_dir(d, "--csv-dir")?;
    }
    if let Some(d) = plots {
        check_output_dir(d, "--plots")?;
    }
    Ok(())
}

/// Write `path` (`-`: standard output), creating its directory.
fn write_file(path: &Path, body: impl FnOnce(&mut dyn Write) -> Result<()>) -> Result<()> {
    if is_stdout(path) {
        let mut w = std::io::BufWriter::new(std::io::stdout().lock());
        body(&mut w).context("writing standard output")?;
        w.flush()?;
        return Ok(());
    }
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("cannot create {}", parent.display()))?;
    }
    let f =
        std::fs::File::create(path).with_context(|| format!("cannot create {}", path.display()))?;
    let mut w = std::io::BufWriter::new(f);
    body(&mut w)
        .and_then(|()| Ok(w.flush()?))
        .map_err(|e| crate::exit::Runtime(format!("writing {}: {e:#}", path.display())))?;
    Ok(())
}

fn fmt(v: Option<f64>) -> String {
    match v {
        Some(x) if x != 0.0 && (x.abs() < 1e-3 || x.abs() >= 1e5) => format!("{x:.4e}"),
        Some(x) => format!("{x:.4}"),
        None => "-".into(),
    }
}

fn print_tables(report: &TradeReport, elapsed: f64) {
    let partial = if report.complete {
        String::new()
    } else {
        format!(" of {} asked (interrupted)", report.runs)
    };
    println!(
        "scenario {}  runs {}{partial}  seed {}  ({elapsed:.2} s wall)",
        report.scenario, report.runs_completed, report.seed
    );
    for f in &report.filters {
        println!();
        println!("filter {}", f.name);
        println!(
            "  {:<20} {:>14} {:>14} {:>14} {:>14} {:>10}",
            "state", "RMSE time-avg", "MAE (eq. 69)", "RMSE final", "mean err final", "in 3σ"
        );
        let mut names: Vec<&String> = report.states.iter().collect();
        let extra = ["pos_m", "vel_mps", "downrange_m", "crossrange_m", "up_m"].map(String::from);
        names.extend(extra.iter());
        for s in names {
            let get =
                |m: &std::collections::BTreeMap<String, Option<f64>>| m.get(s).copied().flatten();
            let in3 = get(&f.within_3sigma_frac)
                .map(|v| format!("{:.1}%", 100.0 * v))
                .unwrap_or_default();
            println!(
                "  {:<20} {:>14} {:>14} {:>14} {:>14} {:>10}",
                s,
                fmt(get(&f.rmse_time_avg)),
                fmt(get(&f.mae_time_avg_eq69)),
                fmt(get(&f.rmse_final)),
                fmt(get(&f.final_error_mean)),
                in3
            );
        }
        print_consistency(f);
    }
    print_pcrlb(report);
}

/// The scenario's PCRLB and each filter's efficiency RMSE / PCRLB (1 = the best any estimator
/// could do with the scenario's information).
fn print_pcrlb(report: &TradeReport) {
    let Some(b) = &report.pcrlb else { return };
    println!();
    if !b.available {
        println!(
            "PCRLB: not available ({})",
            b.reason.as_deref().unwrap_or("unknown reason")
        );
        return;
    }
    let get =
        |m: &std::collections::BTreeMap<String, Option<f64>>, k: &str| m.get(k).copied().flatten();
    println!(
        "PCRLB (lower bound on any estimator's RMSE): pos {} m time-avg, {} m final; vel {} m/s time-avg, {} m/s final",
        fmt(get(&b.time_avg, "pos_m")),
        fmt(get(&b.final_, "pos_m")),
        fmt(get(&b.time_avg, "vel_mps")),
        fmt(get(&b.final_, "vel_mps"))
    );
    println!("  prior: {}", b.prior);
    for f in &report.filters {
        println!(
            "  {:<10} efficiency RMSE/PCRLB: pos {} time-avg, {} final; vel {} time-avg, {} final",
            f.name,
            fmt(get(&f.efficiency_time_avg, "pos_m")),
            fmt(get(&f.efficiency_final, "pos_m")),
            fmt(get(&f.efficiency_time_avg, "vel_mps")),
            fmt(get(&f.efficiency_final, "vel_mps"))
        );
    }
}

fn print_consistency(f: &FilterReport) {
    let c = &f.consistency;
    let pct = |v: Option<f64>| {
        v.map(|v| format!("{:.0}%", 100.0 * v))
            .unwrap_or_else(|| "-".into())
    };
    let per_dof = |a: Option<f64>, dof: f64| a.map(|a| format!("{:.3}", a / dof));
    println!(
        "  ANEES {} (dof {}, /dof {}, per-epoch 95% bounds [{:.3}, {:.3}], {} of epochs inside)",
        fmt(c.anees),
        c.nees_dof,
        per_dof(c.anees, c.nees_dof as f64).unwrap_or_else(|| "-".into()),
        c.nees_bounds_95[0],
        c.nees_bounds_95[1],
        pct(c.nees_in_bounds_frac)
    );
    println!(
        "  ANEES kinematic {} (dof 6, /dof {}, bounds [{:.3}, {:.3}], {} inside)",
        fmt(c.anees_kinematic),
        per_dof(c.anees_kinematic, 6.0).unwrap_or_else(|| "-".into()),
        c.nees_kinematic_bounds_95[0],
        c.nees_kinematic_bounds_95[1],
        pct(c.nees_kinematic_in_bounds_frac)
    );
    if let (Some(anis), Some(dof)) = (c.anis, c.nis_dof) {
        let channels: Vec<String> = c
            .nis_per_channel
            .iter()
            .map(|(name, n)| format!("{name} {:.3}", n.anis_per_dof))
            .collect();
        println!(
            "  ANIS {} (dof {dof:.2}, /dof {}, bounds [{:.3}, {:.3}], {} of epochs inside); per channel /dof: {}",
            fmt(Some(anis)),
            fmt(c.anis_per_dof),
            c.nis_bounds_95[0],
            c.nis_bounds_95[1],
            pct(c.nis_in_bounds_frac),
            channels.join(", ")
        );
    }
    if let Some(d) = f.density_rmspe_pct {
        let at_est = f
            .density_at_estimate_rmspe_pct
            .map(|v| format!("{v:.4} %"))
            .unwrap_or_else(|| "-".into());
        println!(
            "  density RMSPE (eq. 70) {d:.4} % (onboard profile at the true altitude); {at_est} at the estimate"
        );
    }
    if let Some(e) = &f.ellipse_km {
        println!(
            "  deployment 3σ ellipse: {:.3} × {:.3} km at {:.1}° from downrange, mean offset ({:.3}, {:.3}) km",
            e.semi_major_km,
            e.semi_minor_km,
            e.orientation_deg,
            e.mean_downrange_km,
            e.mean_crossrange_km
        );
    }
    println!(
        "  failed {} of {} runs (numerical), diverged {} (final NEES > 100 x dof); {:.2} µs per filter step",
        f.failed, f.runs, f.diverged, f.us_per_step
    );
    for p in &f.failures {
        println!(
            "    run {} at t = {} s ({}): {}",
            p.run,
            p.t_s,
            match p.kind {
                entrynav::sim::metrics::ProblemKind::Numerical => "numerical",
                entrynav::sim::metrics::ProblemKind::Nees => "NEES",
            },
            p.reason
        );
    }
    let bad = f.failed + f.diverged;
    if bad * 100 > f.runs {
        println!(
            "  WARNING: {bad} of {} runs ({:.1}%) failed or diverged; replay one with --replay-run RUN --csv-dir DIR",
            f.runs,
            100.0 * bad as f64 / f.runs.max(1) as f64
        );
    }
}

fn write_csv_dir(dir: &Path, report: &TradeReport) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    if let Some(b) = report.pcrlb.as_ref().filter(|b| b.available) {
        let path = dir.join(format!("{}_pcrlb.csv", report.scenario));
        write_file(&path, |w| {
            let names: Vec<&String> = b.series.keys().collect();
            let header: Vec<String> = names.iter().map(|n| format!("pcrlb_{n}")).collect();
            writeln!(w, "t_s,{}", header.join(","))?;
            for (k, t) in b.times_s.iter().enumerate() {
                let row: Vec<String> = names.iter().map(|n| b.series[*n][k].to_string()).collect();
                writeln!(w, "{t},{}", row.join(","))?;
            }
            Ok(())
        })?;
    }
    let path = dir.join(format!("{}_final_errors.csv", report.scenario));
    write_file(&path, |w| {
        let mut header = vec!["run".to_string(), "filter".into(), "status".into()];
        header.extend(report.states.iter().map(|s| format!("err_{s}")));
        header.extend(["pos_m", "vel_mps", "nees"].map(String::from));
        writeln!(w, "{}", header.join(","))?;
        let o = |v: Option<f64>| v.map(|x| x.to_string()).unwrap_or_default();
        for f in &report.filters {
            for r in &f.final_errors {
                let mut row = vec![r.run.to_string(), f.name.clone(), r.status.clone()];
                row.extend((0..report.states.len()).map(|i| o(r.err.get(i).copied().flatten())));
                row.extend([o(r.pos_m), o(r.vel_mps), o(r.nees)]);
                writeln!(w, "{}", row.join(","))?;
            }
        }
        Ok(())
    })?;
    for f in &report.filters {
        let path = dir.join(format!("{}_{}.csv", report.scenario, f.name));
        write_file(&path, |w| {
            let s = &f.series;
            let mut header = vec!["t_s".to_string()];
            for st in &report.states {
                header.push(format!("rmse_{st}"));
                header.push(format!("sigma_mean_{st}"));
                header.push(format!("bias_{st}"));
            }
            header.extend(
                [
                    "rmse_pos_m",
                    "rmse_vel_mps",
                    "nees_mean",
                    "density_rms_pct",
                    "density_mean_pct",
                    "density_at_estimate_rms_pct",
                ]
                .map(String::from),
            );
            let nw = s.weights_mean.iter().map(|w| w.len()).max().unwrap_or(0);
            header.extend((0..nw).map(|j| format!("weight_{j}")));
            writeln!(w, "{}", header.join(","))?;
            let o = |v: Option<f64>| v.map(|x| x.to_string()).unwrap_or_default();
            for (k, t) in s.times_s.iter().enumerate() {
                let mut row = vec![t.to_string()];
                for i in 0..report.states.len() {
                    row.push(o(s.rmse[k][i]));
                    row.push(o(s.sigma_mean[k][i]));
                    row.push(o(s.bias[k][i]));
                }
                row.extend([
                    o(s.pos_rmse_m[k]),
                    o(s.vel_rmse_mps[k]),
                    o(s.nees_mean[k]),
                    o(s.density_rms_pct[k]),
                    o(s.density_mean_pct[k]),
                    o(s.density_at_estimate_rms_pct[k]),
                ]);
                for j in 0..nw {
                    row.push(
                        s.weights_mean[k]
                            .get(j)
                            .map(|v| v.to_string())
                            .unwrap_or_default(),
                    );
                }
                writeln!(w, "{}", row.join(","))?;
            }
            Ok(())
        })?;
    }
    Ok(())
}
