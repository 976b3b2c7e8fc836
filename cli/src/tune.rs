//! `entrynav tune`: the process-noise diagonal (and optionally the assumed measurement noise) that
//! makes each of a scenario's filters consistent, filter by filter, validated on fresh runs with
//! the file as written, and written as the input scenario's own text with one
//! `[filter.tuned.<name>]` table per filter (`crate::tuned_file`).

use crate::tuned_file::{self, Retune};
use anyhow::{Context, Result, bail};
use clap::Args;
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::{FilterRetuneConfig, ScenarioConfig, builtin_toml};
use entrynav::sim::monte_carlo::report::FilterReport;
use entrynav::sim::monte_carlo::tuning::TuningRuns;
use entrynav_loader as load;
use entrynav_optimizer::tune::{
    EntryTuning, TuneObjective, TuneOptions, TuneResult, TuningProblem, objective, tune,
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
    /// Filter(s) to make consistent, comma-separated: each is tuned on its own and gets its own
    /// `[filter.tuned.<name>]` in the written file.
    #[arg(long, visible_alias = "filters", default_value = "ekf")]
    filter: String,
    /// Write the scenario here: the input's text with its comments and layout, plus one
    /// `[filter.tuned.<name>]` table per tuned filter.
    #[arg(long, value_name = "TUNED.toml")]
    out: PathBuf,
    /// Monte Carlo runs of the tuning set (common random numbers: every evaluation sees them).
    #[arg(long, default_value_t = 24, allow_hyphen_values = true, value_parser = crate::exit::parse_runs)]
    runs: usize,
    /// Master seed of the tuning runs (the validation runs use a different one).
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Runs of the fresh validation set.
    #[arg(long, default_value_t = 100, allow_hyphen_values = true, value_parser = crate::exit::parse_runs)]
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

/// Smallest relative drop of the objective for which a tuning is written: below it the
/// factors only fit the tuning runs' noise.
const MIN_GAIN: f64 = 0.10;

/// Seed of the validation runs: a different study than the tuning runs.
fn validation_seed(seed: u64) -> u64 {
    seed.wrapping_add(0x5EED_0000_0000_0001)
}

/// Run the command.
pub fn run(args: &TuneArgs) -> Result<()> {
    crate::threads::with_threads(args.threads, || run_tuning(args))
}

/// One filter's tuning.
struct Tuned {
    kind: FilterKind,
    /// Name, factor, and whether it sits at its search bound.
    factors: Vec<(String, f64, bool)>,
    result: TuneResult,
    search_s: f64,
    /// What the file holds for it (six significant digits).
    retune: FilterRetuneConfig,
    /// Why its tuning is kept as it was (no table written), if it is.
    kept: Option<String>,
}

/// The scenario's TOML text as the user wrote it (the built-in's text for a built-in).
fn source_text(origin: &load::Origin) -> Result<String> {
    match origin {
        load::Origin::Builtin(name) => builtin_toml(name)
            .map(str::to_string)
            .ok_or_else(|| anyhow::anyhow!("no text for built-in scenario {name}")),
        load::Origin::File(path) => {
            load::read_text(path).with_context(|| format!("cannot read {}", path.display()))
        }
    }
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
    let src = load::resolve(&args.scenario, load::Base::CurrentDir)?;
    let source = source_text(&src.origin)?;
    let (cfg, dir) = src.into_parts();
    let cfg = load::apply_overrides(cfg, &args.sets)?;
    crate::exit::warn_implausible(&cfg);
    let scenario = load::build(cfg.clone(), &dir)?;
    let kinds = FilterKind::parse_list(&args.filter, &scenario.onboard)?;
    let clock = std::time::Instant::now();
    let runs = TuningRuns::record(&scenario, args.seed, args.runs)?;
    let fresh = TuningRuns::record(&scenario, validation_seed(args.seed), args.validation_runs)?;
    let opts = TuneOptions {
        objective: if args.nis_only {
            TuneObjective::NisOnly
        } else {
            TuneObjective::NeesAndNis
        },
        max_evaluations: args.max_evaluations,
        ..Default::default()
    };
    let mut tuned = Vec::new();
    for &kind in &kinds {
        tuned.push(tune_one(args, &opts, &runs, &cfg, kind)?);
    }

    // What the written file does: the scenario built from its own text, on both run sets.
    let plain: Vec<Retune<'_>> = tuned
        .iter()
        .filter(|t| t.kept.is_none())
        .map(|t| Retune {
            name: t.kind.name(),
            config: &t.retune,
            comment: &[],
        })
        .collect();
    let text = tuned_file::edit(&source, &args.sets, &plain)?;
    let written = check_written(&text, &cfg, &tuned)?;
    let tuned_scenario = load::build(written.clone(), &dir)?;
    let (old, new) = (&scenario.onboard, &tuned_scenario.onboard);
    let tuning_before = runs.evaluate(old, &kinds)?;
    let tuning_after = runs.evaluate(new, &kinds)?;
    let before = fresh.evaluate(old, &kinds)?;
    let after = fresh.evaluate(new, &kinds)?;
    let wall_s = clock.elapsed().as_secs_f64();

    let worse = crate::tune_verdict::worse_figures(&before, &after);
    let summary = Summary {
        name: &scenario.config.name,
        wall_s,
        tuned: &tuned,
        tuning: (&tuning_before, &tuning_after),
        fresh: (&before, &after),
    };
    if !worse.is_empty() && !args.force {
        print_summary(args, &opts, &summary);
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
    let comments: Vec<Vec<String>> = tuned
        .iter()
        .zip(before.iter().zip(&after))
        .filter(|(t, _)| t.kept.is_none())
        .map(|(t, (b, a))| {
            let mut lines = comment_lines(args, &opts, t, b, a);
            let name = format!("{}:", t.kind.name());
            lines.extend(
                worse
                    .iter()
                    .filter(|w| w.starts_with(&name))
                    .map(|w| format!("NOTE: written with --force although worse: {w}")),
            );
            lines
        })
        .collect();
    let with_comments: Vec<Retune<'_>> = tuned
        .iter()
        .filter(|t| t.kept.is_none())
        .zip(&comments)
        .map(|(t, c)| Retune {
            name: t.kind.name(),
            config: &t.retune,
            comment: c,
        })
        .collect();
    let text = tuned_file::edit(&source, &args.sets, &with_comments)?;
    if check_written(&text, &cfg, &tuned)? != written {
        bail!("internal error: the commented tuned file differs from the one validated");
    }
    // The file first: a closed standard output (`| head`) must not cost it.
    crate::atomic_file::write(&args.out, text)?;
    print_summary(args, &opts, &summary);
    println!("wrote {}", args.out.display());
    Ok(())
}

/// What `tune` prints.
struct Summary<'a> {
    name: &'a str,
    wall_s: f64,
    tuned: &'a [Tuned],
    tuning: (&'a [FilterReport], &'a [FilterReport]),
    fresh: (&'a [FilterReport], &'a [FilterReport]),
}

fn print_summary(args: &TuneArgs, opts: &TuneOptions, s: &Summary<'_>) {
    let (scenario_name, wall_s, tuned) = (s.name, s.wall_s, s.tuned);
    let (tuning_before, tuning_after) = s.tuning;
    let (before, after) = s.fresh;
    println!(
        "tuned {} on {} ({} tuning runs, seed {}; {wall_s:.1} s in all): each filter its own Q",
        args.filter, scenario_name, args.runs, args.seed
    );
    for t in tuned {
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
            sig3(objective(&t.result.initial, opts.objective)),
            sig3(t.result.cost),
            objective_zero(args.nis_only)
        );
        for (name, f, at_bound) in &t.factors {
            let bound = if *at_bound {
                "  (at the search bound)"
            } else {
                ""
            };
            println!("    {name:<40} x {}{bound}", tuned_file::six_digits(*f));
        }
    }
    print_comparison("tuning runs", tuning_before, tuning_after);
    print_comparison(
        &format!(
            "validation: {} fresh runs (seed {})",
            args.validation_runs,
            validation_seed(args.seed)
        ),
        before,
        after,
    );
}

/// Tune filter `kind` from its current tuning.
fn tune_one(
    args: &TuneArgs,
    opts: &TuneOptions,
    runs: &TuningRuns,
    cfg: &ScenarioConfig,
    kind: FilterKind,
) -> Result<Tuned> {
    let clock = std::time::Instant::now();
    let problem = EntryTuning::new(runs, kind, args.tune_noise)?;
    let bar = if args.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new(args.max_evaluations as u64)
    };
    bar.set_style(
        ProgressStyle::with_template(&format!(
            "{{spinner}} tuning {} [{{bar:40}}] {{pos}}/{{len}} evaluations, {{msg}}",
            kind.name()
        ))
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> "),
    );
    let result = tune(&problem, opts, &|done, _, best| {
        bar.set_position(done as u64);
        bar.set_message(format!("best J {best:.3e}"));
    })?;
    bar.finish_and_clear();
    let factors = problem
        .groups()
        .iter()
        .zip(&result.theta)
        .enumerate()
        .map(|(k, (g, t))| {
            let (lo, hi) = problem.bounds(k);
            let at_bound = *t <= lo + 1e-9 || *t >= hi - 1e-9;
            (g.name().to_string(), 10f64.powf(*t), at_bound)
        })
        .collect();
    let retune = tuned_file::rounded(&problem.retune_config(cfg, &result.theta));
    let initial_j = objective(&result.initial, opts.objective);
    let kept = if result.already_consistent {
        Some(format!(
            "already consistent on the tuning runs (ANEES/dof {}, ANIS/dof {}, within {} %, no \
             failure)",
            fmt(result.initial.anees_per_dof),
            fmt(result.initial.anis_per_dof),
            100.0 * opts.consistent_within
        ))
    } else if result.cost > (1.0 - MIN_GAIN) * initial_j {
        Some(format!(
            "no factor lowered J by {:.0} % ({} evaluations, J {} -> {}): Q does not limit this \
             filter's consistency (try --tune-noise)",
            100.0 * MIN_GAIN,
            result.evaluations,
            sig3(initial_j),
            sig3(result.cost)
        ))
    } else {
        None
    };
    Ok(Tuned {
        kind,
        factors,
        result,
        search_s: clock.elapsed().as_secs_f64(),
        retune,
        kept,
    })
}

/// The configuration `text` holds, checked to be `cfg` with exactly the tunings in `tuned`.
fn check_written(text: &str, cfg: &ScenarioConfig, tuned: &[Tuned]) -> Result<ScenarioConfig> {
    let written = ScenarioConfig::from_toml_str(text, "the tuned scenario")?;
    let mut expected = cfg.clone();
    for t in tuned.iter().filter(|t| t.kept.is_none()) {
        expected
            .filter
            .tuned
            .insert(t.kind.name().to_string(), t.retune.clone());
    }
    if written != expected {
        bail!(
            "internal error: the tuned file does not read back as the tuned scenario (the --set \
             overrides or the [filter.tuned] tables were not written as applied)"
        );
    }
    Ok(written)
}

fn sig3(x: f64) -> String {
    format!("{x:.2e}")
}

fn objective_zero(nis_only: bool) -> &'static str {
    if nis_only {
        "ANIS/dof 1"
    } else {
        "ANEES/dof and ANIS/dof both 1"
    }
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

/// The comment above a filter's `[filter.tuned.<name>]` table: how it was tuned and what it does.
fn comment_lines(
    args: &TuneArgs,
    opts: &TuneOptions,
    t: &Tuned,
    before: &FilterReport,
    after: &FilterReport,
) -> Vec<String> {
    let mut flags = String::new();
    if args.nis_only {
        flags.push_str(" --nis-only");
    }
    if args.tune_noise {
        flags.push_str(" --tune-noise");
    }
    for s in &args.sets {
        flags.push_str(&format!(" --set {s}"));
    }
    let factors: Vec<String> = t
        .factors
        .iter()
        .map(|(n, f, _)| format!("{n} x {}", tuned_file::six_digits(*f)))
        .collect();
    let pct = |r: &FilterReport| {
        r.consistency
            .nees_in_bounds_frac
            .map_or("-".into(), |f| format!("{:.1} %", 100.0 * f))
    };
    vec![
        format!(
            "{}: its own tuning, by `entrynav tune --scenario {} --filter {}{flags} --runs {} --seed {}`",
            t.kind.name(),
            args.scenario,
            args.filter,
            args.runs,
            args.seed
        ),
        format!(
            "Nelder-Mead over log10 factors from the previous tuning, {} evaluations, J {} -> {} with",
            t.result.evaluations,
            sig3(objective(&t.result.initial, opts.objective)),
            sig3(t.result.cost)
        ),
        format!(
            "  J = {}",
            match opts.objective {
                TuneObjective::NeesAndNis =>
                    "ln^2(ANEES/dof) + ln^2(ANIS/dof) + 25 x (failed or diverged fraction)",
                TuneObjective::NisOnly => "ln^2(ANIS/dof) + 25 x (failed or diverged fraction)",
            }
        ),
        format!("factors: {}", factors.join(", ")),
        format!(
            "fresh validation, {} runs (seed {}): ANEES/dof {} -> {}, epochs in the NEES band {} -> {}, \
             ANIS/dof {} -> {},",
            args.validation_runs,
            validation_seed(args.seed),
            fmt(per_dof(before)),
            fmt(per_dof(after)),
            pct(before),
            pct(after),
            fmt(before.consistency.anis_per_dof),
            fmt(after.consistency.anis_per_dof),
        ),
        format!(
            "  position RMSE time-averaged {} -> {} m, final {} -> {} m",
            fmt(crate::tune_verdict::rmse_avg(before)),
            fmt(crate::tune_verdict::rmse_avg(after)),
            fmt(crate::tune_verdict::rmse_final(before)),
            fmt(crate::tune_verdict::rmse_final(after)),
        ),
    ]
}
