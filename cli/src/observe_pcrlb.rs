//! `entrynav observe --pcrlb`: the scenario's posterior Cramér–Rao lower bound from its truth
//! runs alone, without running a filter (the same bound `entrynav trade` reports beside the
//! RMSE; see `entrynav::sim::bounds::pcrlb`).

use anyhow::{Result, bail};
use entrynav::scenario::Scenario;
use entrynav::sim::monte_carlo::state_names;
use entrynav::sim::{PcrlbReport, pcrlb_study};
use std::time::Instant;

/// Most truth runs `--runs` accepts for the bound.
pub const MAX_PCRLB_RUNS: usize = 100_000;

/// Compute the bound over `runs` truth runs of master seed `seed` and print it.
pub fn run(scenario: &Scenario, runs: usize, seed: u64) -> Result<PcrlbReport> {
    if !(1..=MAX_PCRLB_RUNS).contains(&runs) {
        bail!("--runs {runs}: the PCRLB needs 1..={MAX_PCRLB_RUNS} truth runs");
    }
    let started = Instant::now();
    let report = pcrlb_study(scenario, seed, runs)?;
    let elapsed = started.elapsed().as_secs_f64();
    println!();
    if !report.available {
        println!(
            "PCRLB: not available ({})",
            report.reason.as_deref().unwrap_or("unknown reason")
        );
        return Ok(report);
    }
    println!(
        "PCRLB over {runs} truth runs (seed {seed}, {elapsed:.2} s): the lowest RMSE any unbiased \
         estimator can reach on this scenario, in the units of `trade`'s RMSE tables"
    );
    println!("  prior: {}", report.prior);
    println!("  {:<14} {:>14} {:>14}", "state", "time-avg", "final");
    let mut names = state_names(scenario);
    names.extend(["pos_m".to_string(), "vel_mps".to_string()]);
    for name in &names {
        let get =
            |m: &std::collections::BTreeMap<String, Option<f64>>| m.get(name).copied().flatten();
        println!(
            "  {:<14} {:>14} {:>14}",
            name,
            num(get(&report.time_avg)),
            num(get(&report.final_))
        );
    }
    Ok(report)
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
