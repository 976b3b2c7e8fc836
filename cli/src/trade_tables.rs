//! The tables `entrynav trade` (and `trade merge`) prints: per filter the RMSE and final errors
//! per state, consistency (ANEES, ANIS), failures; then the PCRLB and each filter's efficiency.

use entrynav::sim::{FilterReport, TradeReport};
use std::collections::BTreeMap;

/// A table cell: four decimals, scientific notation outside [1e-3, 1e5), `-` when absent.
fn fmt(v: Option<f64>) -> String {
    match v {
        Some(x) if x != 0.0 && (x.abs() < 1e-3 || x.abs() >= 1e5) => format!("{x:.4e}"),
        Some(x) => format!("{x:.4}"),
        None => "-".into(),
    }
}

/// Print the tables of `report` (`wall`: the study's wall time, in words); `list_runs`: every
/// failed or diverged run under its filter's table, not only their counts.
pub fn print_tables(report: &TradeReport, wall: &str, list_runs: bool) {
    let partial = if report.complete {
        String::new()
    } else {
        format!(" of {} asked (interrupted)", report.runs)
    };
    println!(
        "scenario {}  runs {}{partial}  seed {}  ({wall})",
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
            let get = |m: &BTreeMap<String, Option<f64>>| m.get(s).copied().flatten();
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
        // Where and why a filter that ran is inconsistent (a diverging one has its own line).
        if !entrynav_studies::trade::expected::mostly_bad(f) {
            let problems = entrynav_studies::diagnosis::diagnose(f, &report.states);
            if !problems.is_empty() {
                println!("  diagnosis: {}", problems.join("; "));
            }
        }
        print_bad_runs(f, list_runs);
    }
    print_pcrlb(report);
    println!();
    println!(
        "recommendation: {}",
        entrynav_render::report::summary::recommendation(report)
    );
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
    let get = |m: &BTreeMap<String, Option<f64>>, k: &str| m.get(k).copied().flatten();
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
    if let Some(g) = &f.gating {
        print_gating(g);
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
}

/// The failed and diverged runs of `f`, one line each when `list` (the first 20 of each kind: the
/// report keeps those), and the line for more than 1 % of them: a WARNING, or what the paper
/// that predicts it says (`entrynav_studies::trade::expected`).
fn print_bad_runs(f: &FilterReport, list: bool) {
    if list {
        for p in &f.failures {
            println!(
                "    run {} at t = {} s ({}): {}",
                p.run,
                p.t_s,
                match p.kind {
                    entrynav::sim::monte_carlo::metrics::ProblemKind::Numerical => "numerical",
                    entrynav::sim::monte_carlo::metrics::ProblemKind::Nees => "NEES",
                },
                p.reason
            );
        }
    }
    let replay = "replay one with --replay-run RUN --csv-dir DIR";
    match entrynav_studies::trade::expected::bad_runs_line(f) {
        Some(line) if list => println!("  {line}; {replay}"),
        Some(line) => println!("  {line}; list them with --list-runs, {replay}"),
        None if !list && !f.failures.is_empty() => {
            println!("  list the failed or diverged runs with --list-runs, {replay}")
        }
        None => {}
    }
}

/// The innovation gate's line and, per excluded beacon, its detections.
fn print_gating(g: &entrynav::sim::monte_carlo::gate_stats::GatingSummary) {
    println!(
        "  gate: {:.3} % of measurements rejected, ANIS/dof before gating {}; runs with a false beacon exclusion {:.1} %",
        100.0 * g.rejected_frac,
        fmt(g.anis_before_gating_per_dof),
        100.0 * g.false_exclusion_run_frac
    );
    for (beacon, b) in &g.per_beacon {
        println!(
            "    {beacon}: excluded after its fault in {} of {} runs ({} within 10 s; mean {} s, longest {} s), falsely in {} runs",
            b.detected_runs,
            g.runs,
            b.detected_within_10s_frac
                .map(|v| format!("{:.1} %", 100.0 * v))
                .unwrap_or_else(|| "-".into()),
            fmt(b.detection_mean_s),
            fmt(b.detection_max_s),
            b.false_exclusion_runs
        );
    }
}
