//! `entrynav lincov`: LinCov of a filter along the scenario's nominal trajectory
//! (`entrynav::sim::lincov_entry`): the predicted true RMSE, the filter's own σ and the predicted
//! NEES in one pass, optionally beside a Monte Carlo of the same filter (`--compare-mc RUNS`)
//! with both wall times.

use anyhow::{Context, Result};
use entrynav::scenario::Scenario;
use entrynav::sim::FilterReport;
use entrynav::sim::TradeReport;
use entrynav::sim::lincov::{EntryLinCov, EntryLinCovEpoch};
use entrynav_studies::ScenarioInput;
use entrynav_studies::lincov::document::write_csv;
use entrynav_studies::lincov::{Analysed, LinCovStudyOptions, mean_error_nees, run_lincov};
use std::collections::BTreeMap;
use std::path::PathBuf;

/// Arguments of `entrynav lincov`.
#[derive(clap::Args, Debug)]
pub struct LinCovArgs {
    /// Built-in scenario name or path to a scenario TOML file.
    #[arg(long)]
    scenario: String,
    /// The `--set` overrides.
    #[command(flatten)]
    overrides: crate::args::SetArgs,
    /// Comma-separated filters to analyse (LinCov supports: ekf, the consider EKF included, ukf as its EKF equivalent, and the fusion filters ci and dcifaif).
    #[arg(long, visible_alias = "filters", default_value = "ekf")]
    filter: String,
    /// Write the result as JSON (`-`: to standard output, and no table).
    #[arg(long)]
    json: Option<PathBuf>,
    /// Write per-filter per-epoch series (`lincov_<filter>.csv`) into this directory.
    #[arg(long)]
    csv_dir: Option<PathBuf>,
    /// Also run a Monte Carlo of RUNS runs of the same filters (as `trade --runs RUNS`) and
    /// print it beside the prediction, with both wall times.
    #[arg(long, value_name = "RUNS")]
    compare_mc: Option<usize>,
    /// Master seed of the `--compare-mc` Monte Carlo.
    #[arg(long, default_value_t = 1, allow_hyphen_values = true, value_parser = crate::args::seed)]
    seed: u64,
    /// Worker threads of the `--compare-mc` Monte Carlo (default: all cores).
    #[arg(long, allow_hyphen_values = true, value_parser = crate::args::threads)]
    threads: Option<usize>,
    /// Carry the second-order mean drift of every filter's time update (the bias a curved model
    /// gives a large error, e.g. a CI local's drag at a km-sized altitude error); 2N more time
    /// updates per epoch. The default first-order LinCov is the one validated on every built-in.
    #[arg(long)]
    second_order_mean: bool,
}

/// Run the command.
pub fn run(args: &LinCovArgs) -> Result<()> {
    crate::preflight::check_output_files(&[(args.json.as_deref(), "--json")])?;
    if let Some(d) = &args.csv_dir {
        crate::preflight::check_output_dir(d, "--csv-dir")?;
    }
    let scenario = ScenarioInput::resolve(&args.scenario, &args.overrides.sets)?.build()?;
    let options = LinCovStudyOptions {
        filters: args.filter.clone(),
        compare_mc: args.compare_mc,
        seed: args.seed,
        threads: args.threads,
        second_order_mean: args.second_order_mean,
    };
    let study = run_lincov(&scenario, &args.scenario, &options)?;
    let value = study.to_json(&scenario);
    let to_stdout = args.json.as_deref().is_some_and(|p| p.as_os_str() == "-");
    if !to_stdout {
        print_table(&scenario, &study.analysed, study.monte_carlo.as_ref());
    }
    if let Some(dir) = &args.csv_dir {
        std::fs::create_dir_all(dir).with_context(|| format!("--csv-dir {}", dir.display()))?;
        for a in &study.analysed {
            let path = dir.join(format!("lincov_{}.csv", a.lincov.filter));
            crate::csv_file::write(&path, |w| Ok(write_csv(w, &a.lincov)?))?;
            if !to_stdout {
                println!("wrote {}", path.display());
            }
        }
    }
    if let Some(path) = &args.json {
        let text = serde_json::to_string_pretty(&value)? + "\n";
        if to_stdout {
            print!("{text}");
        } else {
            entrynav_studies::output::atomic_file::write(path, text)?;
            println!("wrote {}", path.display());
        }
    }
    Ok(())
}

/// A table row: label, time-average and final prediction, the Monte Carlo's two.
type Row<'a> = (&'a str, f64, f64, Option<f64>, Option<f64>);

/// Print the predictions (and the Monte Carlo beside them).
pub(crate) fn print_table(
    scenario: &Scenario,
    analysed: &[Analysed],
    mc: Option<&(TradeReport, f64)>,
) {
    println!(
        "LinCov along the nominal trajectory of '{}'",
        scenario.config.name
    );
    for a in analysed {
        let l = &a.lincov;
        println!(
            "\n{} ({} epochs, {} truth parameters, {:.3} s)",
            l.filter,
            l.epochs.len(),
            l.parameters.len(),
            a.seconds
        );
        for n in &l.notes {
            println!("  note: {n}");
        }
        let mc_f = mc.and_then(|(r, _)| r.filters.iter().find(|f| f.name == l.filter));
        println!(
            "  {:<24} {:>12} {:>12} {:>12} {:>12}",
            "", "time-avg", "final", "MC time-avg", "MC final"
        );
        let rows = rows_of(l, mc_f);
        for (name, avg, fin, mavg, mfin) in rows {
            let o = |v: Option<f64>| v.map_or("-".to_string(), |v| format!("{v:.5}"));
            println!(
                "  {:<24} {:>12.5} {:>12.5} {:>12} {:>12}",
                name,
                avg,
                fin,
                o(mavg),
                o(mfin)
            );
        }
    }
    if mc.is_some() {
        println!(
            "\nthe mean error's share of NEES/dof, m̄ᵀP⁻¹m̄/dof, uses LinCov's onboard P for both; the \
             Monte Carlo's has a sampling floor of about (NEES/dof)/runs, and a share above it that \
             LinCov does not predict is a second-order mean error (docs/results.md)"
        );
    }
    if let Some((report, seconds)) = mc {
        let lincov_s: f64 = analysed.iter().map(|a| a.seconds).sum();
        println!(
            "\nwall time: LinCov {lincov_s:.4} s, Monte Carlo of {} runs {seconds:.3} s ({:.0}×)",
            report.runs,
            seconds / lincov_s.max(1e-12)
        );
    }
}

/// The rows of one filter's table: its prediction beside the Monte Carlo's figures.
fn rows_of(l: &EntryLinCov, mc_f: Option<&FilterReport>) -> [Row<'static>; 6] {
    let mc_get = |m: Option<&BTreeMap<String, Option<f64>>>, k: &str| {
        m.and_then(|m| m.get(k).copied().flatten())
    };
    let bias = mean_error_nees(l, None);
    let mc_bias = mc_f.map(|f| mean_error_nees(l, Some(f)));
    [
        (
            "pos RMSE [m]",
            l.time_avg(|e| e.pos_m),
            l.final_value(|e| e.pos_m),
            mc_get(mc_f.map(|f| &f.rmse_time_avg), "pos_m"),
            mc_get(mc_f.map(|f| &f.rmse_final), "pos_m"),
        ),
        (
            "vel RMSE [m/s]",
            l.time_avg(|e| e.vel_mps),
            l.final_value(|e| e.vel_mps),
            mc_get(mc_f.map(|f| &f.rmse_time_avg), "vel_mps"),
            mc_get(mc_f.map(|f| &f.rmse_final), "vel_mps"),
        ),
        (
            "onboard pos σ [m]",
            l.time_avg(|e| e.pos_sigma_m),
            l.final_value(|e| e.pos_sigma_m),
            None,
            None,
        ),
        (
            "onboard vel σ [m/s]",
            l.time_avg(|e| e.vel_sigma_mps),
            l.final_value(|e| e.vel_sigma_mps),
            None,
            None,
        ),
        (
            "NEES / dof",
            l.nees_ratio_time_avg(),
            l.final_value(EntryLinCovEpoch::nees_per_dof),
            mc_f.and_then(|f| {
                let c = &f.consistency;
                c.anees.map(|a| a / c.nees_dof.max(1) as f64)
            }),
            None,
        ),
        (
            "  of it, the mean error",
            bias.0,
            bias.1,
            mc_bias.map(|b| b.0),
            mc_bias.map(|b| b.1),
        ),
    ]
}
