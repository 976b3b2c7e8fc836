//! `entrynav trade`: Monte Carlo comparison of navigation filters on a scenario.
//!
//! One invocation does one of six things, decided once from its arguments ([`Mode`]): compare two
//! summaries, merge shard files, run a grid, replay one run, run one shard, or run (or resume) a
//! study. The study layer (`entrynav_studies::trade`) does the work; this file loads the
//! scenario, prints what the study says and writes its files (`trade_outputs.rs`); the tables are
//! in `trade_tables.rs`.

use crate::preflight::is_stdout;
use crate::progress::RunProgress;
pub use crate::trade_args::{Method, TradeAction, TradeArgs};
use crate::trade_checkpoint::SummaryCheckpoints;
use crate::trade_lincov::{curves, print_comparison};
use crate::trade_merge::merge;
use crate::trade_outputs::{
    Outputs, check_outputs, command_line, read_resume_file, write_csv_dir, write_text,
};
use crate::trade_tables::print_tables;
use anyhow::{Context, Result};
use entrynav::sim::{Checkpoint, NoCheckpoint, Shard};
use entrynav_render::chart::labels::WeightNames;
use entrynav_studies::ScenarioInput;
use entrynav_studies::progress::Step;
use entrynav_studies::provenance::Provenance;
use entrynav_studies::trade::options::{TradeMode, TradeOptions};
use entrynav_studies::trade::setup::{TradeScenario, TradeSetup};
use entrynav_studies::trade::shard::run_trade_shard;
use entrynav_studies::trade::study::{TradeOutcome, run_trade_study};
use std::path::{Path, PathBuf};

/// What one `trade` invocation does, decided once from its arguments (clap has already refused
/// the combinations that conflict).
enum Mode<'a> {
    /// `trade compare A B`: compare two summaries.
    Compare(&'a crate::compare::CompareArgs),
    /// `trade merge SHARDS…`: combine shard files into the study's report.
    Merge {
        shards: &'a [PathBuf],
        json: Option<&'a Path>,
        csv_dir: Option<&'a Path>,
        plots: Option<&'a Path>,
        list_runs: bool,
    },
    /// `--grid FILE`: scenarios × variations × filters.
    Grid(&'a Path),
    /// `--replay-run K --csv-dir DIR`: one run's full series.
    Replay { run: usize, csv_dir: &'a Path },
    /// `--shard I/N --json FILE`: one shard of a study.
    Shard { shard: Shard, json: &'a Path },
    /// A study, or the continuation of an interrupted one (`--resume FILE`).
    Study { resume: Option<&'a Path> },
}

impl<'a> Mode<'a> {
    fn of(args: &'a TradeArgs) -> Result<Mode<'a>> {
        match &args.action {
            Some(TradeAction::Compare(c)) => return Ok(Mode::Compare(c)),
            Some(TradeAction::Merge {
                shards,
                json,
                csv_dir,
                plots,
                quiet: _,
                list_runs,
            }) => {
                return Ok(Mode::Merge {
                    shards,
                    json: json.as_deref(),
                    csv_dir: csv_dir.as_deref(),
                    plots: plots.as_deref(),
                    list_runs: *list_runs,
                });
            }
            None => {}
        }
        if let Some(grid) = &args.grid {
            return Ok(Mode::Grid(grid));
        }
        if let Some(run) = args.replay_run {
            let csv_dir = args
                .csv_dir
                .as_deref()
                .context("--replay-run needs --csv-dir DIR")?;
            return Ok(Mode::Replay { run, csv_dir });
        }
        if let Some(spec) = &args.shard {
            let shard = Shard::parse(spec)?;
            let json = args
                .json
                .as_deref()
                .context("--shard needs --json FILE to write the shard to")?;
            return Ok(Mode::Shard { shard, json });
        }
        Ok(Mode::Study {
            resume: args.resume.as_deref(),
        })
    }
}

/// Run the command.
pub fn run(args: &TradeArgs) -> Result<()> {
    let mode = Mode::of(args)?;
    let options = args.options();
    if args.method != Method::Mc {
        check_method(args, &options, &mode)?;
    }
    match mode {
        Mode::Compare(c) => crate::compare::run(c),
        Mode::Merge {
            shards,
            json,
            csv_dir,
            plots,
            list_runs,
        } => merge(shards, json, csv_dir, plots, list_runs),
        Mode::Grid(grid) => {
            let html = args.report.as_deref();
            crate::grid::run(grid, options.method, &args.out_dir, html, args.quiet)
        }
        Mode::Replay { run, csv_dir } => {
            let setup = load(args, &options)?;
            crate::replay::write_replay(&setup, &options, run, csv_dir)
        }
        Mode::Shard { shard, json } => run_one_shard(args, &options, shard, json),
        Mode::Study { .. } if args.method == Method::Lincov => {
            let setup = load(args, &options)?;
            let (json, csv_dir) = (args.json.as_deref(), args.csv_dir.as_deref());
            crate::trade_lincov::run_lincov(&setup, &options, json, csv_dir)
        }
        Mode::Study { resume } => run_study(args, &options, resume),
    }
}

/// `--method lincov|both` is a study's option: refuse the modes and outputs it has no meaning
/// for, naming the flag (exit code 2).
fn check_method(args: &TradeArgs, options: &TradeOptions, mode: &Mode<'_>) -> Result<()> {
    let mode = match mode {
        Mode::Study { resume } => TradeMode::Study {
            resume: resume.is_some(),
        },
        Mode::Grid(_) => TradeMode::Grid,
        Mode::Shard { .. } => TradeMode::Shard,
        Mode::Replay { .. } => TradeMode::Replay,
        Mode::Compare(_) | Mode::Merge { .. } => {
            let why = "they read finished summaries";
            return Err(options.refuse("trade compare/merge", why).into());
        }
    };
    if args.method == Method::Lincov && mode == (TradeMode::Study { resume: false }) {
        let of_mc = "of the Monte Carlo; use --method both";
        if args.plots.is_some() {
            return Err(options
                .refuse("--plots", &format!("the plots are {of_mc}"))
                .into());
        }
        if args.report.is_some() {
            return Err(options
                .refuse("--report", &format!("the report is {of_mc}"))
                .into());
        }
    }
    Ok(options.check_mode(mode)?)
}

/// The study's scenario, filters and runs, once its output paths are checked; the scenario's
/// warnings and notes are printed as they come.
fn load(args: &TradeArgs, options: &TradeOptions) -> Result<TradeSetup> {
    check_outputs(
        args.json.as_deref(),
        args.csv_dir.as_deref(),
        args.plots.as_deref(),
    )?;
    crate::report::check_path(args.report.as_deref())?;
    let scenario_name = args.scenario.as_deref().context("--scenario is required")?;
    let input = ScenarioInput::resolve(scenario_name, &args.overrides.sets)?;
    crate::preflight::warn_implausible(&input.config);
    let input = input.with_truth_atmosphere(&args.truth_atmosphere(), args.no_perturbation)?;
    let built = TradeScenario::build(&input)?;
    print_warnings(&built.warnings);
    for n in &built.notes {
        eprintln!("note: {n}");
    }
    Ok(TradeSetup::new(built, options)?)
}

fn print_warnings(warnings: &[String]) {
    for w in warnings {
        eprintln!("warning: {w}");
    }
}

/// Run shard `shard` of the study and write its block sums to `path`; an interrupted shard is
/// not written (a shard must be complete to merge).
fn run_one_shard(
    args: &TradeArgs,
    options: &TradeOptions,
    shard: Shard,
    path: &Path,
) -> Result<()> {
    let setup = load(args, options)?;
    let cancel = Some(crate::interrupt::install());
    let file = run_trade_shard(&setup, options, shard, cancel)?;
    for n in &file.notes {
        eprintln!("note: {n}");
    }
    if let Some(e) = file.interruption() {
        return Err(e.into());
    }
    print_warnings(&file.warnings);
    write_text(path, &file.to_json()?)?;
    eprintln!(
        "wrote shard {}/{} ({} blocks) of {} runs to {}",
        shard.index,
        shard.count,
        file.result.blocks.len(),
        setup.runs,
        path.display()
    );
    Ok(())
}

/// Run the study (or continue the interrupted one in `resume`), print its tables and write its
/// outputs; an interrupted study writes its partial results and ends interrupted.
fn run_study(args: &TradeArgs, options: &TradeOptions, resume: Option<&Path>) -> Result<()> {
    let to_file = args.json.as_deref().is_some_and(|p| !is_stdout(p));
    let every = options.checkpoint_interval(to_file)?;
    let setup = load(args, options)?;
    let previous = resume.map(read_resume_file).transpose()?;
    let provenance = setup.provenance(command_line());
    let mut checkpoints: Box<dyn Checkpoint + Send> = match (every, args.json.as_deref()) {
        (Some(s), Some(path)) => Box::new(SummaryCheckpoints::new(path, s, provenance.clone())),
        _ => Box::new(NoCheckpoint),
    };
    let progress = RunProgress::new(setup.runs, args.quiet, setup.label(options));
    let step = |s: Step<'_>| progress.set(s.done as usize);
    let cancel = Some(crate::interrupt::install());
    let outcome = run_trade_study(
        &setup,
        options,
        previous,
        checkpoints.as_mut(),
        cancel,
        &step,
    )?;
    progress.finish();
    let report = &outcome.report;
    if !report.complete {
        eprintln!(
            "interrupted: {} of {} runs completed; writing the partial results",
            report.runs_completed, report.runs
        );
    }
    print_warnings(&outcome.warnings);
    write_results(args, &setup, &outcome, &provenance)?;
    match outcome.interruption() {
        Some(e) => Err(e.into()),
        None => Ok(()),
    }
}

/// Write every output asked for, then print the tables (unless the JSON goes to standard
/// output) and what was written. Files come first, so a closed standard output (`… | head`)
/// never costs one; every output is attempted, and a failed one (exit code 1) does not skip
/// the others.
fn write_results(
    args: &TradeArgs,
    setup: &TradeSetup,
    outcome: &TradeOutcome,
    provenance: &Provenance,
) -> Result<()> {
    let (report, delivery) = (&outcome.report, outcome.delivery.as_ref());
    // With `--json -` the JSON is standard output: no tables, notes to stderr.
    let to_stdout = args.json.as_deref().is_some_and(is_stdout);
    let mut outputs = Outputs::default();
    if let Some(path) = &args.json {
        let done = outcome
            .to_json(provenance)
            .map_err(Into::into)
            .and_then(|text| write_text(path, &text));
        let note = (!to_stdout).then(|| format!("wrote {}", path.display()));
        outputs.record(done.map(|()| note));
    }
    if let Some(dir) = &args.csv_dir {
        let done = write_csv_dir(dir, report);
        outputs.record(done.map(|()| Some(format!("wrote CSV series to {}", dir.display()))));
    }
    let names = WeightNames::of_scenario(&setup.scenario);
    let extra = outcome
        .lincov
        .as_ref()
        .map(|c| curves(c, report))
        .unwrap_or_default();
    if let Some(dir) = &args.plots {
        let done = crate::figures::trade_plots(dir, report, &names, &extra, delivery);
        outputs.record(done.map(|()| Some(format!("wrote plots to {}", dir.display()))));
    }
    if let Some(path) = &args.report {
        let elapsed = outcome.wall_s;
        let done = crate::report::write_trade(
            path,
            report,
            &names,
            provenance,
            elapsed,
            outcome.lincov.as_ref(),
            delivery,
        );
        outputs.record(done.map(|s| Some(format!("wrote report {} in {s:.3} s", path.display()))));
    }
    if !to_stdout {
        print_tables(
            report,
            &format!("{:.2} s wall", outcome.wall_s),
            args.list_runs,
        );
        if let Some(c) = &outcome.lincov {
            print_comparison(c, report);
        }
        if let Some(d) = delivery {
            println!();
            crate::guidance::print_table(d);
        }
    }
    outputs.finish(to_stdout)
}
