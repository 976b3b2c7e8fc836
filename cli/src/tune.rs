//! `entrynav tune`: the command over the tuning study (`entrynav_studies::tune`): the process-noise
//! diagonal (and optionally the assumed measurement noise) that makes each of a scenario's
//! filters consistent, filter by filter, validated on fresh runs; prints the summary and writes
//! the input scenario's own text with one `[filter.tuned.<name>]` table per filter.

use anyhow::{Context, Result};
use clap::Args;
use entrynav::sim::monte_carlo::report::FilterReport;
use entrynav_studies::ScenarioInput;
use entrynav_studies::progress::Step;
use entrynav_studies::tune::figures::{band, fmt, objective_zero, per_dof, sig3};
use entrynav_studies::tune::tuned_file::six_digits;
use entrynav_studies::tune::verdict::{rmse_avg, rmse_final};
use entrynav_studies::tune::{TuneStudy, TuneStudyOptions, run_tune};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::PathBuf;
use std::sync::Mutex;

/// Arguments of `entrynav tune`.
#[derive(Args)]
pub struct TuneArgs {
    /// Built-in scenario name or path to a scenario TOML file.
    #[arg(long)]
    scenario: String,
    /// The `--set` overrides.
    #[command(flatten)]
    overrides: crate::args::SetArgs,
    /// Filter(s) to make consistent, comma-separated: each is tuned on its own and gets its own
    /// `[filter.tuned.<name>]` in the written file.
    #[arg(long, visible_alias = "filters", default_value = "ekf")]
    filter: String,
    /// Write the scenario here: the input's text with its comments and layout, plus one
    /// `[filter.tuned.<name>]` table per tuned filter.
    #[arg(long, value_name = "TUNED.toml")]
    out: PathBuf,
    /// Monte Carlo runs of the tuning set (common random numbers: every evaluation sees them).
    #[arg(long, default_value_t = 24, allow_hyphen_values = true, value_parser = crate::args::runs)]
    runs: usize,
    /// Master seed of the tuning runs (the validation runs use a different one).
    #[arg(long, default_value_t = 1, allow_hyphen_values = true, value_parser = crate::args::seed)]
    seed: u64,
    /// Runs of the fresh validation set.
    #[arg(long, default_value_t = 100, allow_hyphen_values = true, value_parser = crate::args::validation_runs)]
    validation_runs: usize,
    /// Tune on innovations alone (ANIS/dof -> 1): what a flight team has without the truth.
    #[arg(long)]
    nis_only: bool,
    /// Also tune a factor on the assumed measurement noise per channel kind.
    #[arg(long)]
    tune_noise: bool,
    /// Evaluation budget of the search.
    #[arg(long, default_value_t = 150)]
    max_evaluations: usize,
    /// The worker pool.
    #[command(flatten)]
    workers: crate::args::ThreadsArg,
    /// Write the tuned file even when a primary figure is worse than the input's on the fresh
    /// validation runs beyond the Monte Carlo noise (position RMSE, failed or diverged runs,
    /// |ln ANEES/dof|, |ln ANIS/dof|).
    #[arg(long)]
    force: bool,
    #[arg(long, help = crate::args::QUIET_HELP)]
    quiet: bool,
}

/// Run the command.
pub fn run(args: &TuneArgs) -> Result<()> {
    crate::preflight::check_output_file(&args.out, "--out")?;
    let options = TuneStudyOptions {
        filters: args.filter.clone(),
        runs: args.runs,
        seed: args.seed,
        validation_runs: args.validation_runs,
        nis_only: args.nis_only,
        tune_noise: args.tune_noise,
        max_evaluations: args.max_evaluations,
        threads: args.workers.threads,
        force: args.force,
    };
    options.validate()?;
    if let Some(parent) = args.out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("cannot create {}", parent.display()))?;
    }
    let input = ScenarioInput::resolve(&args.scenario, &args.overrides.sets)?;
    crate::preflight::warn_implausible(&input.config);
    let bar = Bars::default();
    let progress = |step: Step<'_>| bar.show(step, args.quiet);
    let study = run_tune(&input, &options, &progress);
    bar.clear();
    let study = study?;
    if let Some(refused) = study.refusal(&args.out) {
        print_summary(&study);
        for w in &study.worse {
            eprintln!("warning: worse than the input on fresh runs: {w}");
        }
        return Err(refused.into());
    }
    // The file first: a closed standard output (`| head`) must not cost it.
    if let Some(text) = &study.text {
        entrynav_studies::output::atomic_file::write(&args.out, text)?;
    }
    print_summary(&study);
    println!("wrote {}", args.out.display());
    // Written, and said: a tuning still inconsistent ends the command with a failure, as a design
    // worse than its input does.
    match study.inconsistency(&args.out) {
        Some(e) => Err(e.into()),
        None => Ok(()),
    }
}

/// One progress bar per filter tuned, replaced when the next filter starts.
#[derive(Default)]
struct Bars(Mutex<Option<(String, ProgressBar)>>);

impl Bars {
    fn show(&self, step: Step<'_>, quiet: bool) {
        let Ok(mut slot) = self.0.lock() else { return };
        if slot.as_ref().is_none_or(|(task, _)| task != step.task) {
            if let Some((_, old)) = slot.take() {
                old.finish_and_clear();
            }
            let bar = if quiet {
                ProgressBar::hidden()
            } else {
                ProgressBar::new(step.total)
            };
            bar.set_style(
                ProgressStyle::with_template(&format!(
                    "{{spinner}} tuning {} [{{bar:40}}] {{pos}}/{{len}} evaluations, {{msg}}",
                    step.task
                ))
                .unwrap_or_else(|_| ProgressStyle::default_bar())
                .progress_chars("=> "),
            );
            *slot = Some((step.task.to_string(), bar));
        }
        if let Some((_, bar)) = slot.as_ref() {
            bar.set_position(step.done);
            if let Some(best) = step.best {
                bar.set_message(format!("best J {best:.3e}"));
            }
        }
    }

    fn clear(&self) {
        if let Some((_, bar)) = self.0.lock().ok().and_then(|mut s| s.take()) {
            bar.finish_and_clear();
        }
    }
}

fn print_summary(s: &TuneStudy) {
    let o = &s.options;
    println!(
        "tuned {} on {} ({} tuning runs, seed {}; {:.1} s in all): each filter its own Q",
        o.filters, s.scenario, o.runs, o.seed, s.wall_s
    );
    for t in &s.tuned {
        if let Some(why) = &t.kept {
            println!(
                "  {}: {why}; its tuning is kept and no table is written for it",
                t.kind.name()
            );
            continue;
        }
        println!(
            "  {}: {} evaluations, {:.1} s; objective J {} -> {} on the tuning runs (0 = {})",
            t.kind.name(),
            t.result.evaluations,
            t.search_s,
            sig3(t.initial_cost),
            sig3(t.result.cost),
            objective_zero(o.nis_only)
        );
        for f in &t.factors {
            let bound = if f.at_bound {
                "  (at the search bound)"
            } else {
                ""
            };
            println!("    {:<40} x {}{bound}", f.name, six_digits(f.factor));
        }
    }
    print_comparison("tuning runs", &s.tuning.0, &s.tuning.1);
    print_comparison(
        &format!(
            "validation: {} fresh runs (seed {})",
            o.validation_runs,
            s.validation_seed()
        ),
        &s.fresh.0,
        &s.fresh.1,
    );
}

fn print_comparison(title: &str, before: &[FilterReport], after: &[FilterReport]) {
    println!("  {title}:");
    println!(
        "    {:<10} {:>7} {:>10} {:>9} {:>9} {:>15} {:>15} {:>16} {:>11}",
        "filter",
        "",
        "ANEES/dof",
        "in band",
        "ANIS/dof",
        "pos RMSE avg m",
        "pos RMSE fin m",
        "vel RMSE avg m/s",
        "failed/div"
    );
    for (b, a) in before.iter().zip(after) {
        for (label, r) in [("before", b), ("after", a)] {
            println!(
                "    {:<10} {:>7} {:>10} {:>9} {:>9} {:>15} {:>15} {:>16} {:>11}",
                r.name,
                label,
                fmt(per_dof(r)),
                band(r),
                fmt(r.consistency.anis_per_dof),
                fmt(rmse_avg(r)),
                fmt(rmse_final(r)),
                fmt(r.rmse_time_avg.get("vel_mps").copied().flatten()),
                format!("{}/{}", r.failed, r.diverged)
            );
        }
    }
}
