//! `entrynav tune`: the process-noise diagonal (and optionally the assumed measurement noise) that
//! makes a scenario's filters consistent, validated on fresh runs, written as a scenario file.

use anyhow::{Context, Result, bail};
use clap::Args;
use entrynav::estimation::nav::FilterKind;
use entrynav::sim::report::FilterReport;
use entrynav::sim::tuning::TuningRuns;
use entrynav_loader as load;
use entrynav_optimizer::tune::{
    EntryTuning, TuneObjective, TuneOptions, TuningProblem, entry::measured, tune,
};
use indicatif::{ProgressBar, ProgressStyle};
use std::path::PathBuf;

/// Arguments of `entrynav tune`.
#[derive(Args)]
pub struct TuneArgs {
    /// Built-in scenario name or path to a scenario TOML file.
    #[arg(long)]
    scenario: String,
    /// Override a scenario field before tuning: PATH=VALUE in TOML syntax (repeatable).
    #[arg(long = "set", value_name = "PATH=VALUE")]
    sets: Vec<String>,
    /// Filter(s) to make consistent, comma-separated (one Q serves them all: the objective is
    /// their mean).
    #[arg(long, default_value = "ekf")]
    filter: String,
    /// Write the scenario with the tuned values here.
    #[arg(long, value_name = "TUNED.toml")]
    out: PathBuf,
    /// Monte Carlo runs of the tuning set (common random numbers: every evaluation sees them).
    #[arg(long, default_value_t = 24)]
    runs: usize,
    /// Master seed of the tuning runs (the validation runs use a different one).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Runs of the fresh validation set.
    #[arg(long, default_value_t = 100)]
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
    /// Worker threads (default: all cores).
    #[arg(long, value_parser = crate::exit::parse_threads)]
    threads: Option<usize>,
    /// Write the tuned file even when it makes a filter worse than the input on the fresh
    /// validation runs (band fraction or position RMSE by more than 10 %).
    #[arg(long)]
    force: bool,
    #[arg(long, help = crate::QUIET_HELP)]
    quiet: bool,
}

/// Seed of the validation runs: a different study than the tuning runs.
fn validation_seed(seed: u64) -> u64 {
    seed.wrapping_add(0x5EED_0000_0000_0001)
}

/// Run the command.
pub fn run(args: &TuneArgs) -> Result<()> {
    crate::threads::with_threads(args.threads, || run_tuning(args))
}

fn run_tuning(args: &TuneArgs) -> Result<()> {
    if !(1..=100_000).contains(&args.runs) || !(1..=100_000).contains(&args.validation_runs) {
        bail!(
            "--runs {} / --validation-runs {}: each must be between 1 and 100000",
            args.runs,
            args.validation_runs
        );
    }
    if let Some(parent) = args.out.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("cannot create {}", parent.display()))?;
    }
    let (cfg, dir) = load::resolve(&args.scenario, load::Base::CurrentDir)?.into_parts();
    let cfg = load::apply_overrides(cfg, &args.sets)?;
    let scenario = load::build(cfg.clone(), &dir)?;
    let kinds = FilterKind::parse_list(&args.filter, &scenario.onboard)?;
    let clock = std::time::Instant::now();
    let runs = TuningRuns::record(&scenario, args.seed, args.runs)?;
    let problem = EntryTuning::new(&runs, &kinds, args.tune_noise)?;
    let bar = if args.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(args.max_evaluations as u64)
    };
    bar.set_style(
        ProgressStyle::with_template("{spinner} tuning [{bar:40}] {pos}/{len} evaluations, {msg}")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    let opts = TuneOptions {
        objective: if args.nis_only {
            TuneObjective::NisOnly
        } else {
            TuneObjective::NeesAndNis
        },
        max_evaluations: args.max_evaluations,
        ..Default::default()
    };
    let result = tune(&problem, &opts, &|done, _, best| {
        bar.set_position(done as u64);
        bar.set_message(format!("best J {best:.3e}"));
    })?;
    bar.finish_and_clear();
    let search_s = clock.elapsed().as_secs_f64();
    let fresh = TuningRuns::record(&scenario, validation_seed(args.seed), args.validation_runs)?;
    let zero = vec![0.0; problem.dim()];
    let before = problem.reports(&zero, &fresh)?;
    let after = problem.reports(&result.theta, &fresh)?;
    let tuning_before = problem.reports(&zero, &runs)?;
    let tuning_after = problem.reports(&result.theta, &runs)?;
    let wall_s = clock.elapsed().as_secs_f64();

    println!(
        "tuned {} on {} ({} tuning runs, seed {}; {} evaluations, {search_s:.1} s search, {wall_s:.1} s in all)",
        args.filter, scenario.config.name, args.runs, args.seed, result.evaluations
    );
    println!("  factors (x base value):");
    for (g, t) in problem.groups().iter().zip(&result.theta) {
        println!("    {:<40} {:>12.4e}", g.name(), 10f64.powf(*t));
    }
    print_comparison("tuning runs", &tuning_before, &tuning_after);
    print_comparison(
        &format!(
            "validation: {} fresh runs (seed {})",
            args.validation_runs,
            validation_seed(args.seed)
        ),
        &before,
        &after,
    );
    let warnings = rmse_warnings(&before, &after);
    for w in &warnings {
        println!("  NOTE: {w}");
    }
    println!(
        "  objective J: {:.3e} before, {:.3e} after (tuning runs; 0 = ANEES/dof and ANIS/dof both 1)",
        entrynav_optimizer::tune::objective(&result.initial, opts.objective),
        result.cost
    );
    let worse = crate::tune_verdict::worse_figures(&before, &after);
    if !worse.is_empty() && !args.force {
        for w in &worse {
            eprintln!("warning: worse than the input on fresh runs: {w}");
        }
        return Err(crate::exit::Runtime(format!(
            "{} not written: the tuning makes a filter worse than the input on the {} fresh \
             validation runs ({}); --force writes it anyway",
            args.out.display(),
            args.validation_runs,
            worse.join("; ")
        ))
        .into());
    }
    let tuned = problem.tuned_config(&cfg, &result.theta);
    let mut notes = warnings;
    notes.extend(
        worse
            .iter()
            .map(|w| format!("written with --force although worse: {w}")),
    );
    let header = header_comment(args, &problem, &result, &before, &after, &notes);
    let text = format!(
        "{header}{}",
        crate::tune_verdict::compact_numbers(&tuned.to_toml_string())
    );
    crate::atomic_file::write(&args.out, text)?;
    println!("wrote {}", args.out.display());
    Ok(())
}

fn fmt(v: Option<f64>) -> String {
    v.map(|x| format!("{x:.4}")).unwrap_or_else(|| "-".into())
}

fn per_dof(r: &FilterReport) -> Option<f64> {
    r.consistency
        .anees
        .map(|a| a / r.consistency.nees_dof.max(1) as f64)
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
            let band = r
                .consistency
                .nees_in_bounds_frac
                .map_or("-".into(), |f| format!("{:.1} %", 100.0 * f));
            println!(
                "    {:<10} {:>7} {:>10} {:>9} {:>9} {:>15} {:>15} {:>16} {:>11}",
                r.name,
                label,
                fmt(per_dof(r)),
                band,
                fmt(r.consistency.anis_per_dof),
                fmt(crate::tune_verdict::rmse_avg(r)),
                fmt(crate::tune_verdict::rmse_final(r)),
                fmt(r.rmse_time_avg.get("vel_mps").copied().flatten()),
                format!("{}/{}", r.failed, r.diverged)
            );
        }
    }
}

/// Tuned filters whose validation position RMSE is more than 10 % worse than untuned.
fn rmse_warnings(before: &[FilterReport], after: &[FilterReport]) -> Vec<String> {
    before
        .iter()
        .zip(after)
        .filter_map(|(b, a)| {
            let get = |r: &FilterReport| r.rmse_time_avg.get("pos_m").copied().flatten();
            let (rb, ra) = (get(b)?, get(a)?);
            (ra > 1.1 * rb).then(|| {
                format!(
                    "{}: the tuned filter's time-averaged position RMSE is {:.0} % worse ({ra:.4} m vs {rb:.4} m): consistency costs accuracy here (the untuned filter was overconfident)",
                    a.name,
                    100.0 * (ra / rb - 1.0)
                )
            })
        })
        .collect()
}

fn header_comment(
    args: &TuneArgs,
    problem: &EntryTuning<'_>,
    result: &entrynav_optimizer::tune::TuneResult,
    before: &[FilterReport],
    after: &[FilterReport],
    warnings: &[String],
) -> String {
    let mut h = String::new();
    h.push_str(&format!(
        "# Tuned by `entrynav tune --scenario {} --filter {}{}{} --runs {} --seed {}`\n",
        args.scenario,
        args.filter,
        if args.nis_only { " --nis-only" } else { "" },
        if args.tune_noise { " --tune-noise" } else { "" },
        args.runs,
        args.seed
    ));
    for s in &args.sets {
        h.push_str(&format!("#   with --set {s}\n"));
    }
    h.push_str(&format!(
        "# Nelder-Mead over log10 factors on filter.q_diag groups{}: minimise ln^2(ANEES/dof) + \
         ln^2(ANIS/dof) + 25 x (failed or diverged fraction) on {} runs with common random numbers \
         ({} evaluations).\n",
        if args.tune_noise {
            " and on the assumed noise per channel kind (filter.noise_inflation)"
        } else {
            ""
        },
        args.runs,
        result.evaluations
    ));
    h.push_str("# Factors found:\n");
    for (g, t) in problem.groups().iter().zip(&result.theta) {
        h.push_str(&format!("#   {} x {:.4e}\n", g.name(), 10f64.powf(*t)));
    }
    let (mb, ma) = (measured(before), measured(after));
    h.push_str(&format!(
        "# Validation on {} fresh runs (seed {}): ANEES/dof {} -> {}, ANIS/dof {} -> {}, \
         failed or diverged {:.1} % -> {:.1} %.\n",
        args.validation_runs,
        validation_seed(args.seed),
        fmt(mb.anees_per_dof),
        fmt(ma.anees_per_dof),
        fmt(mb.anis_per_dof),
        fmt(ma.anis_per_dof),
        100.0 * mb.bad_fraction,
        100.0 * ma.bad_fraction
    ));
    for w in warnings {
        h.push_str(&format!("# NOTE: {w}\n"));
    }
    h.push('\n');
    h
}
