//! `trade --method lincov|both`: the trade's statistics predicted by LinCov of each filter
//! instead of, or beside, the Monte Carlo (`entrynav_studies::trade::lincov_comparison`).
//!
//! `lincov` writes what `entrynav lincov` writes (JSON under `lincov`, `lincov_<filter>.csv`
//! series). `both` prints, per filter and headline figure, LinCov's prediction, the Monte
//! Carlo's value, the ratio and the Monte Carlo's 95 % interval, flagging the figures outside it;
//! the RMSE charts get LinCov's curves.

use crate::lincov::print_table;
use anyhow::{Context, Result};
use entrynav::sim::TradeReport;
use entrynav_studies::lincov::document::write_csv;
use entrynav_studies::trade::lincov_comparison::{LinCovComparison, figures};
use entrynav_studies::trade::options::TradeOptions;
use entrynav_studies::trade::setup::TradeSetup;
use entrynav_studies::trade::study::run_trade_lincov;
use std::path::Path;

/// `trade --method lincov`: LinCov of the study's filters; `--json` and `--csv-dir` as
/// `entrynav lincov` writes them (files first).
pub fn run_lincov(
    setup: &TradeSetup,
    options: &TradeOptions,
    json_path: Option<&Path>,
    csv_dir: Option<&Path>,
) -> Result<()> {
    let study = run_trade_lincov(setup, options)?;
    let scenario = &setup.scenario;
    let value = study.to_json(scenario);
    let to_stdout = json_path.is_some_and(|p| p.as_os_str() == "-");
    let mut notes = Vec::new();
    if let Some(dir) = csv_dir {
        std::fs::create_dir_all(dir).with_context(|| format!("--csv-dir {}", dir.display()))?;
        for a in &study.analysed {
            let path = dir.join(format!("lincov_{}.csv", a.lincov.filter));
            crate::csv_file::write(&path, |w| Ok(write_csv(w, &a.lincov)?))?;
            notes.push(format!("wrote {}", path.display()));
        }
    }
    if let Some(path) = json_path {
        let text = serde_json::to_string_pretty(&value)? + "\n";
        if to_stdout {
            print!("{text}");
        } else {
            entrynav_studies::output::atomic_file::write(path, text)?;
            notes.push(format!("wrote {}", path.display()));
        }
    }
    if !to_stdout {
        print_table(scenario, &study.analysed, None);
        for n in notes {
            println!("{n}");
        }
    }
    Ok(())
}

/// LinCov's RMSE curves, dashed, for the RMSE charts of `--plots` and `--report`.
pub fn curves(
    c: &LinCovComparison,
    report: &TradeReport,
) -> entrynav_render::trade_figures::ExtraCurves {
    entrynav_render::trade_figures::lincov_curves(c, report)
}

/// Print LinCov / Monte Carlo per filter, flagging figures outside the Monte Carlo's interval.
pub fn print_comparison(c: &LinCovComparison, report: &TradeReport) {
    println!(
        "\nLinCov beside the Monte Carlo (ratio = LinCov / MC; ! = outside the MC's 95 % interval)"
    );
    for a in &c.analysed {
        let Some(f) = report.filters.iter().find(|f| f.name == a.lincov.filter) else {
            continue;
        };
        println!("\n{} ({} runs; LinCov {:.3} s)", f.name, f.runs, a.seconds);
        for n in &a.lincov.notes {
            println!("  note: {n}");
        }
        println!(
            "  {:<34} {:>12} {:>12} {:>8} {:>25}",
            "figure", "LinCov", "MC", "ratio", "MC 95 % interval"
        );
        let rows = figures(a, f);
        for r in &rows {
            println!(
                "  {:<34} {:>12} {:>12} {:>8.3} {:>12}..{:<12}{}",
                r.figure,
                num(r.lincov),
                num(r.mc),
                r.ratio(),
                num(r.mc - r.half),
                num(r.mc + r.half),
                if r.disagrees() { " !" } else { "" }
            );
        }
        if let Some(why) = entrynav_studies::trade::expected::lincov_disagreement(f, &rows) {
            println!("  warning: {why}");
        }
    }
}

/// Five significant digits: fixed from 0.01 up, scientific below (angles in rad, densities).
fn num(v: f64) -> String {
    if v != 0.0 && v.abs() < 0.01 {
        format!("{v:.4e}")
    } else {
        format!("{v:.5}")
    }
}
