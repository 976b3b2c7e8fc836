//! `entrynav trade`: Monte Carlo comparison of navigation filters on a scenario.
//!
//! One invocation does one of six things, decided once from its arguments ([`Mode`]): compare two
//! summaries, merge shard files, run a grid, replay one run, run one shard, or run (or resume) a
//! study. The tables it prints are in `trade_tables.rs`, the files it writes in `trade_files.rs`.

use crate::atmosphere_file::{check_profile_covers, report_truth_table, truth_atmosphere};
use crate::exit::{check_output_dir, is_stdout};
use crate::interrupt::Interrupted;
use crate::plot::labels::WeightNames;
use crate::progress::RunProgress;
use crate::provenance::Provenance;
use crate::threads::with_threads;
pub use crate::trade_args::{TradeAction, TradeArgs};
use crate::trade_checkpoint::{self, SummaryCheckpoints};
use crate::trade_files::{
    Extras, ReadShards, ShardFile, StudyProvenance, check_outputs, read_resume, read_shards,
    write_csv_dir, write_file, write_summary_with,
};
use crate::trade_lincov::{Comparison, Method};
use crate::trade_tables::print_tables;
use anyhow::{Context, Result};
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::Scenario;
use entrynav::sim::guided::delivery::DeliveryReport;
use entrynav::sim::guided::delivery_shard::{DeliveryShard, deliver_runs, merge_delivery_shards};
use entrynav::sim::monte_carlo::shard::fold_partial;
use entrynav::sim::{
    Checkpoint, McOptions, NoCheckpoint, Shard, ShardResult, TradeReport, merge_shards, run_shard,
};
use entrynav_loader as load;
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
            }) => {
                return Ok(Mode::Merge {
                    shards,
                    json: json.as_deref(),
                    csv_dir: csv_dir.as_deref(),
                    plots: plots.as_deref(),
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
    if args.method != Method::Mc {
        check_method(args, &mode)?;
    }
    match mode {
        Mode::Compare(c) => crate::compare::run(c),
        Mode::Merge {
            shards,
            json,
            csv_dir,
            plots,
        } => merge(shards, json, csv_dir, plots),
        Mode::Grid(grid) => run_grid(args, grid),
        Mode::Replay { run, csv_dir } => {
            let setup = Setup::load(args)?;
            crate::replay::write_replay(&setup.scenario, &setup.filters, args.seed, run, csv_dir)
        }
        Mode::Shard { shard, json } => run_one_shard(args, shard, json),
        Mode::Study { .. } if args.method == Method::Lincov => {
            let setup = Setup::load(args)?;
            crate::trade_lincov::run_lincov(
                &setup.scenario,
                &setup.filters,
                args.json.as_deref(),
                args.csv_dir.as_deref(),
            )
        }
        Mode::Study { resume } => run_study(args, resume),
    }
}

/// `--method lincov|both` is a study's option: refuse the modes and outputs it has no meaning
/// for, naming the flag (exit code 2).
fn check_method(args: &TradeArgs, mode: &Mode<'_>) -> Result<()> {
    let method = match args.method {
        Method::Lincov => "lincov",
        Method::Both => "both",
        Method::Mc => return Ok(()),
    };
    let refuse = |flag: &str, why: &str| -> Result<()> {
        Err(crate::exit::Usage(format!("--method {method} with {flag}: {why}")).into())
    };
    match mode {
        Mode::Study { resume: Some(_) } => {
            return refuse(
                "--resume",
                "only a Monte Carlo study is resumed; use --method mc",
            );
        }
        Mode::Study { resume: None } => {}
        Mode::Grid(_) if args.method == Method::Both => {
            return refuse("--grid", "a grid runs one method: mc or lincov");
        }
        Mode::Grid(_) => {}
        Mode::Shard { .. } => return refuse("--shard", "LinCov is one pass, not sharded"),
        Mode::Replay { .. } => return refuse("--replay-run", "a replay is one Monte Carlo run"),
        Mode::Compare(_) | Mode::Merge { .. } => {
            return refuse("trade compare/merge", "they read finished summaries");
        }
    }
    if args.method == Method::Lincov && matches!(mode, Mode::Study { .. }) {
        if args.plots.is_some() {
            return refuse(
                "--plots",
                "the plots are of the Monte Carlo; use --method both",
            );
        }
        if args.report.is_some() {
            return refuse(
                "--report",
                "the report is of the Monte Carlo; use --method both",
            );
        }
        if args.runs.is_some() {
            return refuse(
                "--runs",
                "LinCov flies no runs; use --method both to compare",
            );
        }
    }
    Ok(())
}

/// The scenario, filters and run count of a study, loaded once its output paths are checked.
struct Setup {
    scenario: Scenario,
    filters: Vec<FilterKind>,
    runs: usize,
}

impl Setup {
    fn load(args: &TradeArgs) -> Result<Setup> {
        check_outputs(
            args.json.as_deref(),
            args.csv_dir.as_deref(),
            args.plots.as_deref(),
        )?;
        crate::report::check_path(args.report.as_deref())?;
        let scenario_name = args.scenario.as_deref().context("--scenario is required")?;
        let (cfg, dir) = load::resolve(scenario_name, load::Base::CurrentDir)?.into_parts();
        let cfg = load::apply_overrides(cfg, &args.sets)?;
        crate::exit::warn_implausible(&cfg);
        let cfg = truth_atmosphere(cfg, &args.atmosphere, args.no_perturbation)?;
        let scenario = load::build(cfg, &dir)?;
        report_truth_table(&scenario);
        if let Some(file) = &args.atmosphere.atmosphere_file {
            check_profile_covers(&scenario, file)?;
        }
        let filters = FilterKind::parse_list(&args.filters, &scenario.onboard)?;
        let runs = args.runs.unwrap_or(scenario.config.monte_carlo.runs);
        Ok(Setup {
            scenario,
            filters,
            runs,
        })
    }

    /// The Monte Carlo options: the PCRLB unless `--no-pcrlb`; Ctrl-C cancels.
    fn options(&self, args: &TradeArgs) -> McOptions {
        McOptions {
            pcrlb: !args.no_pcrlb,
            cancel: Some(crate::interrupt::install()),
            ..McOptions::new(self.runs, args.seed)
        }
    }

    fn provenance(&self, args: &TradeArgs) -> Provenance {
        Provenance::new(&args.sets)
            .with_scenario(&self.scenario, args.atmosphere.atmosphere_file.as_deref())
    }
}

fn run_grid(args: &TradeArgs, grid: &Path) -> Result<()> {
    check_output_dir(&args.out_dir, "--out-dir")?;
    crate::report::check_path(args.report.as_deref())?;
    crate::grid::run(
        grid,
        &args.out_dir,
        args.quiet,
        args.report.as_deref(),
        args.method == Method::Lincov,
    )
}

/// Run shard `shard` of the study and write its block sums to `path`; an interrupted shard is
/// not written (a shard must be complete to merge).
fn run_one_shard(args: &TradeArgs, shard: Shard, path: &Path) -> Result<()> {
    let setup = Setup::load(args)?;
    let blocks = setup
        .runs
        .div_ceil(entrynav::sim::monte_carlo::shard::ACCUMULATION_BLOCK);
    if shard.blocks(setup.runs).is_empty() {
        eprintln!(
            "note: shard {}/{} of this {}-run study holds no runs: a shard holds whole accumulation \
             blocks of {} runs (so that merged shards equal the single-process study bit for bit) \
             and the study has {blocks}; use at most {blocks} shard(s)",
            shard.index,
            shard.count,
            setup.runs,
            entrynav::sim::monte_carlo::shard::ACCUMULATION_BLOCK
        );
    }
    let opts = setup.options(args);
    let clock = std::time::Instant::now();
    let result = with_threads(args.threads, || {
        Ok(run_shard(
            &setup.scenario,
            &setup.filters,
            &opts,
            shard,
            &|_| {},
        )?)
    })?;
    if !result.complete {
        return Err(Interrupted(format!(
            "shard {}/{} not written (a shard must be complete to merge)",
            shard.index, shard.count
        ))
        .into());
    }
    // A scenario with `[guidance]`: the delivery runs of this shard's blocks, merged by run
    // index in `trade merge`. A failure here never costs the shard's sums: it is a warning.
    let delivery = setup
        .scenario
        .config
        .guidance
        .is_some()
        .then(|| {
            let blocks = shard.blocks(setup.runs);
            let block = entrynav::sim::monte_carlo::shard::ACCUMULATION_BLOCK;
            let runs = (blocks.start * block).min(setup.runs)..(blocks.end * block).min(setup.runs);
            with_threads(args.threads, || {
                deliver_runs(&setup.scenario, &setup.filters, setup.runs, args.seed, runs)
                    .context("the delivery at deployment of the shard's runs")
            })
        })
        .and_then(|d| {
            d.map_err(|e| eprintln!("warning: no delivery in this shard: {e:#}"))
                .ok()
        });
    let file = ShardFile {
        shard: &result,
        provenance: StudyProvenance::of(&setup.provenance(args)),
        wall_s: clock.elapsed().as_secs_f64(),
        delivery: delivery.as_ref(),
    };
    write_file(path, |w| Ok(serde_json::to_writer(&mut *w, &file)?))?;
    eprintln!(
        "wrote shard {}/{} ({} blocks) of {} runs to {}",
        shard.index,
        shard.count,
        result.blocks.len(),
        setup.runs,
        path.display()
    );
    Ok(())
}

/// Run the study (or continue the interrupted one in `resume`), print its tables and write its
/// outputs; an interrupted study writes its partial results and ends in [`Interrupted`].
fn run_study(args: &TradeArgs, resume: Option<&Path>) -> Result<()> {
    let every = checkpoint_interval(args)?;
    let setup = Setup::load(args)?;
    let previous = resume.map(read_resume).transpose()?;
    let opts = setup.options(args);
    let clock = std::time::Instant::now();
    let mut checkpoints: Box<dyn Checkpoint + Send> = match (every, args.json.as_deref()) {
        (Some(s), Some(path)) => Box::new(SummaryCheckpoints::new(path, s, setup.provenance(args))),
        _ => Box::new(NoCheckpoint),
    };
    let (report, partial) = fly(args, &setup, &opts, previous, checkpoints.as_mut())?;
    let elapsed = clock.elapsed().as_secs_f64();
    if !report.complete {
        eprintln!(
            "interrupted: {} of {} runs completed; writing the partial results",
            report.runs_completed, report.runs
        );
    }
    let lincov = (args.method == Method::Both && report.complete)
        .then(|| Comparison::of(&setup.scenario, &setup.filters, &report))
        .transpose()?;
    // A scenario with `[guidance]`: the same runs flown with each filter in the guidance loop.
    // A failure here never costs the Monte Carlo's results: it is a warning.
    let delivery = (report.complete && setup.scenario.config.guidance.is_some())
        .then(|| {
            crate::guidance::delivery_of_study(
                &setup.scenario,
                &setup.filters,
                setup.runs,
                args.seed,
                args.threads,
            )
        })
        .and_then(|d| {
            d.map_err(|e| eprintln!("warning: no delivery table: {e:#}"))
                .ok()
        });
    write_results(
        args,
        &setup,
        &report,
        partial.as_ref(),
        elapsed,
        lincov.as_ref(),
        delivery.as_ref(),
    )?;
    if !report.complete {
        return Err(Interrupted(format!(
            "{} of {} runs completed (complete: false in the summary)",
            report.runs_completed, report.runs
        ))
        .into());
    }
    Ok(())
}

/// The checkpoint interval of a study (s), `None` for none: `--checkpoint-every` (0: none),
/// by default [`trade_checkpoint::DEFAULT_EVERY_S`] when the summary goes to a file.
fn checkpoint_interval(args: &TradeArgs) -> Result<Option<f64>> {
    let to_file = args.json.as_deref().is_some_and(|p| !is_stdout(p));
    match args.checkpoint_every {
        Some(s) => {
            trade_checkpoint::check_every(s)?;
            if !to_file && s > 0.0 {
                return Err(crate::exit::Usage(format!(
                    "--checkpoint-every {s} needs --json FILE (the checkpoint is the partial \
                     summary written there)"
                ))
                .into());
            }
            Ok((s > 0.0).then_some(s))
        }
        None => Ok(to_file.then_some(trade_checkpoint::DEFAULT_EVERY_S)),
    }
}

/// Fly the study's runs on `--threads` workers, showing progress and writing checkpoints. A
/// cancelled study's report folds the finished runs and comes with their block sums, which its
/// summary keeps for `--resume`.
fn fly(
    args: &TradeArgs,
    setup: &Setup,
    opts: &McOptions,
    previous: Option<ShardResult>,
    checkpoints: &mut (dyn Checkpoint + Send),
) -> Result<(TradeReport, Option<ShardResult>)> {
    let progress = RunProgress::new(
        setup.runs,
        args.quiet,
        format!("{} × {}", setup.scenario.config.name, args.filters),
    );
    let step = |done: usize| progress.set(done);
    let (scenario, filters) = (&setup.scenario, &setup.filters);
    let study = with_threads(args.threads, || {
        Ok(entrynav::sim::run_study(
            scenario,
            filters,
            opts,
            previous,
            &step,
            checkpoints,
        )?)
    })?;
    let folded = if study.complete {
        (merge_shards(vec![study])?, None)
    } else {
        (fold_partial(study.clone())?, Some(study))
    };
    progress.finish();
    Ok(folded)
}

/// Write every output asked for, then print the tables (unless the JSON goes to standard
/// output) and what was written. Files come first, so a closed standard output (`… | head`)
/// never costs one; every output is attempted, and a failed one (exit code 1) does not skip
/// the others.
fn write_results(
    args: &TradeArgs,
    setup: &Setup,
    report: &TradeReport,
    resume: Option<&ShardResult>,
    elapsed: f64,
    lincov: Option<&Comparison>,
    delivery: Option<&DeliveryReport>,
) -> Result<()> {
    // With `--json -` the JSON is standard output: no tables, notes to stderr.
    let to_stdout = args.json.as_deref().is_some_and(is_stdout);
    let mut outputs = Outputs::default();
    if let Some(path) = &args.json {
        let done = write_summary_with(
            path,
            &setup.provenance(args),
            report,
            resume,
            elapsed,
            Extras {
                lincov: lincov.map(Comparison::json),
                delivery,
            },
        );
        let note = (!to_stdout).then(|| format!("wrote {}", path.display()));
        outputs.record(done.map(|()| note));
    }
    if let Some(dir) = &args.csv_dir {
        let done = write_csv_dir(dir, report);
        outputs.record(done.map(|()| Some(format!("wrote CSV series to {}", dir.display()))));
    }
    let names = WeightNames::of_scenario(&setup.scenario);
    let extra = lincov.map(Comparison::curves).unwrap_or_default();
    if let Some(dir) = &args.plots {
        let done = crate::plots::trade_plots(dir, report, &names, &extra, delivery);
        outputs.record(done.map(|()| Some(format!("wrote plots to {}", dir.display()))));
    }
    if let Some(path) = &args.report {
        let provenance = setup.provenance(args);
        let done = crate::report::write_trade(
            path,
            report,
            &names,
            &provenance,
            elapsed,
            &extra,
            delivery,
        );
        outputs.record(done.map(|s| Some(format!("wrote report {} in {s:.3} s", path.display()))));
    }
    if !to_stdout {
        print_tables(report, &format!("{elapsed:.2} s wall"));
        if let Some(c) = lincov {
            c.print(report);
        }
        if let Some(d) = delivery {
            println!();
            crate::guidance::print_table(d);
        }
    }
    outputs.finish(to_stdout)
}

/// The outputs of a study: what was written (its note) and what failed.
#[derive(Default)]
struct Outputs {
    notes: Vec<String>,
    failures: Vec<anyhow::Error>,
}

impl Outputs {
    fn record(&mut self, done: Result<Option<String>>) {
        match done {
            Ok(note) => self.notes.extend(note),
            Err(e) => self.failures.push(e),
        }
    }

    /// Print the notes (to standard error when standard output carries the JSON); fail with
    /// every failed output named.
    fn finish(self, to_stdout: bool) -> Result<()> {
        for n in &self.notes {
            if to_stdout {
                eprintln!("{n}");
            } else {
                println!("{n}");
            }
        }
        let mut failures = self.failures;
        match failures.len() {
            0 => Ok(()),
            // The work is done: a failure to write it is a runtime failure (exit code 1).
            1 if crate::exit::code(&failures[0]) == 1 => Err(failures.remove(0)),
            _ => {
                let all: Vec<String> = failures.iter().map(|e| format!("{e:#}")).collect();
                Err(crate::exit::Runtime(all.join("; also: ")).into())
            }
        }
    }
}

/// `trade merge`: combine the shard files into the study's report, write the outputs asked for
/// (first, so a closed standard output never costs one), then print the tables. The merged
/// summary keeps the shards' `--set` overrides and atmosphere source; shards that differ in them
/// are refused.
fn merge(
    shards: &[PathBuf],
    json: Option<&Path>,
    csv_dir: Option<&Path>,
    plots: Option<&Path>,
) -> Result<()> {
    check_outputs(json, csv_dir, plots)?;
    let ReadShards {
        parts,
        provenance: study,
        wall_s,
        deliveries,
    } = read_shards(shards)?;
    let n_shards = parts.len();
    let delivery = merged_delivery(deliveries)?;
    let fingerprint = parts
        .first()
        .map(|p| p.scenario_fingerprint.clone())
        .unwrap_or_default();
    let report = merge_shards(parts)?;
    let to_stdout = json.is_some_and(is_stdout);
    let mut outputs = Outputs::default();
    if let Some(path) = json {
        let provenance = Provenance {
            scenario_fingerprint: Some(fingerprint),
            overrides: study.overrides,
            atmosphere: study.atmosphere,
            ..Provenance::new(&[])
        };
        let extras = Extras {
            delivery: delivery.as_ref(),
            ..Extras::default()
        };
        let done = write_summary_with(path, &provenance, &report, None, wall_s, extras);
        let note = (!to_stdout).then(|| format!("wrote {}", path.display()));
        outputs.record(done.map(|()| note));
    }
    if let Some(dir) = csv_dir {
        let done = write_csv_dir(dir, &report);
        outputs.record(done.map(|()| Some(format!("wrote CSV series to {}", dir.display()))));
    }
    let names = WeightNames::of_channels(&report.channels);
    if let Some(dir) = plots {
        let done =
            crate::plots::trade_plots(dir, &report, &names, &Default::default(), delivery.as_ref());
        outputs.record(done.map(|()| Some(format!("wrote plots to {}", dir.display()))));
    }
    if !to_stdout {
        print_tables(
            &report,
            &format!("{wall_s:.2} s wall summed over the {n_shards} shards"),
        );
        if let Some(d) = &delivery {
            crate::guidance::print_table(d);
        }
    }
    outputs.finish(to_stdout)
}

/// The delivery of merged shards: every shard's runs in run order (`None` when no shard has
/// deliveries). Refuses a merge where some shards have deliveries and others not (one flown
/// without `[guidance]`, or by an older entrynav), or whose deliveries do not fit together.
fn merged_delivery(deliveries: Vec<Option<DeliveryShard>>) -> Result<Option<DeliveryReport>> {
    let with = deliveries.iter().filter(|d| d.is_some()).count();
    if with == 0 {
        return Ok(None);
    }
    if with < deliveries.len() {
        return Err(crate::exit::Usage(format!(
            "{with} of {} shards carry a delivery table and the others do not; run the others \
             again with this entrynav",
            deliveries.len()
        ))
        .into());
    }
    let merged = merge_delivery_shards(deliveries.into_iter().flatten().collect())
        .map_err(|e| crate::exit::Usage(format!("trade merge: {e}")))?;
    Ok(Some(merged))
}
