//! `entrynav guidance deliver` (and `reference`, in `guidance_reference`): the command over the
//! delivery study (`entrynav_studies::guidance`), the Monte Carlo of delivery at deployment with
//! navigation filters in the guidance loop, against perfect navigation and the unguided
//! reference bank on the same dispersion draws; its table (also printed by `trade`), JSON and
//! footprint plots.

use crate::preflight::{check_output_file, is_stdout};
use anyhow::{Context, Result};
use clap::{Args, Subcommand};
use entrynav::sim::guided::delivery::{DeliveryReport, DeliveryRow};
use entrynav_studies::ScenarioInput;
use entrynav_studies::guidance::{DeliverOptions, run_deliver};
use entrynav_studies::progress::silent;
use std::path::PathBuf;

/// Arguments of `entrynav guidance`.
#[derive(Args)]
pub struct GuidanceArgs {
    /// What to do.
    #[command(subcommand)]
    pub action: GuidanceAction,
}

/// `entrynav guidance …`.
#[derive(Subcommand)]
pub enum GuidanceAction {
    /// Monte Carlo of delivery at deployment: each filter flown in the guidance loop (its
    /// estimate and the sensed drag go to guidance, the bank through the rate and acceleration
    /// limits drives truth and filter), with perfect navigation and the unguided reference bank
    /// on the same dispersion draws. The scenario needs a `[guidance]` section, e.g.
    /// `--set 'guidance={algorithm="apollo",reference_bank_deg=60.0,trigger={speed_mps=450.0}}'`.
    Deliver(DeliverArgs),
    /// The reference trajectory `[guidance]` builds from the onboard nominal entry at the
    /// reference bank: drag, altitude rate and range to go against speed with the adjoint gains
    /// F1-F3 (summary, `--csv`, `--json`).
    Reference(crate::guidance_reference::ReferenceArgs),
}

/// Arguments of `entrynav guidance deliver`.
#[derive(Args)]
pub struct DeliverArgs {
    /// Built-in scenario name or path to a scenario TOML file (with a `[guidance]` section, or
    /// one given by --set).
    #[arg(long)]
    pub scenario: String,
    /// The `--set` overrides.
    #[command(flatten)]
    pub overrides: crate::args::SetArgs,
    /// Comma-separated filters flown in the loop: ekf, ukf, ci, dcifaif, mmae, mmae-moe, ukf-cm,
    /// ukf-ac, uskf-nn; `none` flies perfect navigation and the unguided bank only.
    #[arg(long, visible_alias = "filter", default_value = "ekf")]
    pub filters: String,
    /// Monte Carlo runs (default: the scenario's monte_carlo.runs).
    #[arg(long, allow_hyphen_values = true, value_parser = crate::args::runs)]
    pub runs: Option<usize>,
    /// Master seed; run r draws its truth from run_seed(seed, r) as `trade` does, and the same
    /// seed gives the same statistics on any thread count.
    #[arg(long, default_value_t = 1, allow_hyphen_values = true, value_parser = crate::args::seed)]
    pub seed: u64,
    /// The worker pool.
    #[command(flatten)]
    pub workers: crate::args::ThreadsArg,
    /// Write the result as JSON (`-`: to standard output, and no table): the rows under
    /// `delivery`, and every run's deliveries under `runs`. Checked before the first run.
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Write the delivery footprints (SVG) into this folder: the guided rows' deployment misses
    /// with their 99 % ellipses and the target, and the unguided bank's.
    #[arg(long, value_name = "DIR")]
    pub plots: Option<PathBuf>,
}

/// Run the command.
pub fn run(args: &GuidanceArgs) -> Result<()> {
    match &args.action {
        GuidanceAction::Deliver(a) => deliver(a),
        GuidanceAction::Reference(a) => crate::guidance_reference::run(a),
    }
}

fn deliver(args: &DeliverArgs) -> Result<()> {
    if let Some(p) = &args.json {
        check_output_file(p, "--json")?;
    }
    if let Some(d) = &args.plots {
        crate::preflight::check_output_dir(d, "--plots")?;
    }
    let input = ScenarioInput::resolve(&args.scenario, &args.overrides.sets)?;
    crate::preflight::warn_implausible(&input.config);
    let scenario = input.build()?;
    let options = DeliverOptions {
        filters: args.filters.clone(),
        runs: args.runs,
        seed: args.seed,
        threads: args.workers.threads,
    };
    let study = run_deliver(&scenario, &options, &silent)?;
    let to_stdout = args.json.as_deref().is_some_and(is_stdout);
    if !to_stdout {
        print_table(&study.report);
    }
    if let Some(path) = &args.json {
        let text = serde_json::to_string_pretty(&study.document())? + "\n";
        if to_stdout {
            print!("{text}");
        } else {
            entrynav_studies::output::atomic_file::write(path, text)
                .with_context(|| format!("writing {}", path.display()))?;
            println!("wrote {}", path.display());
        }
    }
    if let Some(dir) = &args.plots {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        for fig in entrynav_render::delivery_figures::delivery_figures(&study.report)? {
            entrynav_studies::output::atomic_file::write(&dir.join(&fig.file), &fig.svg)?;
        }
        if !to_stdout {
            println!("wrote plots to {}", dir.display());
        }
    }
    Ok(())
}

fn opt(v: Option<f64>, digits: usize) -> String {
    v.map_or_else(|| "-".to_string(), |x| format!("{x:.digits$}"))
}

/// The delivery table (also printed by `trade` for a scenario with `[guidance]`).
pub(crate) fn print_table(r: &DeliveryReport) {
    println!(
        "Delivery at deployment: scenario {}, {} guidance, {} runs, seed {} (bank rate limit {:.1} deg/s)",
        r.scenario, r.algorithm, r.runs, r.seed, r.bank_rate_limit_deg_s
    );
    println!(
        "{:<12} {:>8} {:>6} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>24} {:>9} {:>10} {:>7}",
        "row",
        "deployed",
        "failed",
        "mean [m]",
        "RMS [m]",
        "median [m]",
        "max [m]",
        "mean DR",
        "mean CR",
        "99% ellipse a x b @ deg",
        "max rate",
        "nav [m]",
        "in box"
    );
    for row in &r.rows {
        print_row(row);
    }
    for row in r.rows.iter().filter(|x| x.failures > 0) {
        if let Some((run, why)) = &row.first_failure {
            let causes: Vec<String> = row
                .failures_by_cause
                .iter()
                .map(|(cause, n)| format!("{n} {cause}"))
                .collect();
            println!(
                "{}: {} failed run(s): {}; first: run {run}: {why}",
                row.name,
                row.failures,
                causes.join(", ")
            );
        }
    }
    for w in entrynav_studies::guidance::delivery_warnings::delivery_warnings(r) {
        println!("WARNING: {w}");
    }
    if r.rows.iter().any(|x| !x.rate_limit_held) {
        println!("WARNING: the bank rate exceeded its limit in some run");
    }
}

fn print_row(x: &DeliveryRow) {
    let ellipse = x.ellipse_99.map_or_else(
        || "-".to_string(),
        |e| {
            format!(
                "{:.0} x {:.0} @ {:.1}",
                e.semi_major_m, e.semi_minor_m, e.orientation_deg
            )
        },
    );
    println!(
        "{:<12} {:>8} {:>6} {:>10} {:>10} {:>10} {:>10} {:>10} {:>10} {:>24} {:>9} {:>10} {:>7}",
        x.name,
        x.deployed,
        x.failures,
        opt(x.mean_miss_m, 1),
        opt(x.rms_miss_m, 1),
        opt(x.median_miss_m, 1),
        opt(x.max_miss_m, 1),
        opt(x.mean_downrange_m, 1),
        opt(x.mean_crossrange_m, 1),
        ellipse,
        opt(x.max_bank_rate_deg_s, 2),
        opt(x.rms_nav_position_error_m, 1),
        x.inside_box,
    );
}
