//! `entrynav lincov`: LinCov of a filter along the scenario's nominal trajectory
//! (`entrynav::sim::lincov`): the predicted true RMSE, the filter's own σ and the predicted
//! NEES in one pass, optionally beside a Monte Carlo of the same filter (`--compare-mc RUNS`)
//! with both wall times.

use crate::threads::with_threads;
use anyhow::{Context, Result, bail};
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::Scenario;
use entrynav::sim::lincov::{EntryLinCov, EntryLinCovEpoch, LinCovOptions, entry_lincov_with};
use entrynav::sim::monte_carlo::report::FilterReport;
use entrynav::sim::{McOptions, TradeReport, run_trade};
use entrynav_loader as load;
use serde_json::{Map, Value, json};
use std::collections::BTreeMap;
use std::path::PathBuf;
use std::time::Instant;

/// Most Monte Carlo runs `--compare-mc` accepts.
pub const MAX_COMPARE_RUNS: usize = 20_000;

/// Arguments of `entrynav lincov`.
#[derive(clap::Args, Debug)]
pub struct LinCovArgs {
    /// Built-in scenario name or path to a scenario TOML file.
    #[arg(long)]
    scenario: String,
    /// Override a scenario field: PATH=VALUE in TOML syntax (repeatable).
    #[arg(long = "set", value_name = "PATH=VALUE")]
    sets: Vec<String>,
    /// Comma-separated filters to analyse (LinCov supports: ekf, the consider EKF included, ukf as its EKF equivalent, and the fusion filters ci and dcifaif).
    #[arg(long, default_value = "ekf")]
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
    #[arg(long, default_value_t = 1)]
    seed: u64,
    /// Worker threads of the `--compare-mc` Monte Carlo (default: all cores).
    #[arg(long)]
    threads: Option<usize>,
    /// Carry the second-order mean drift of every filter's time update (the bias a curved model
    /// gives a large error, e.g. a CI local's drag at a km-sized altitude error); 2N more time
    /// updates per epoch. The default first-order LinCov is the one validated on every built-in.
    #[arg(long)]
    second_order_mean: bool,
}

/// One analysed filter with its wall time.
pub(crate) struct Analysed {
    pub(crate) lincov: EntryLinCov,
    pub(crate) seconds: f64,
}

/// LinCov of every filter of `kinds` on `scenario` (named `label` in errors).
pub(crate) fn analyse(
    scenario: &Scenario,
    kinds: &[FilterKind],
    label: &str,
    options: LinCovOptions,
) -> Result<Vec<Analysed>> {
    let mut analysed = Vec::with_capacity(kinds.len());
    for &kind in kinds {
        let started = Instant::now();
        let lincov = entry_lincov_with(scenario, kind, options)
            .with_context(|| format!("LinCov of '{}' on '{label}'", kind.name()))?;
        let seconds = started.elapsed().as_secs_f64();
        analysed.push(Analysed { lincov, seconds });
    }
    Ok(analysed)
}

/// Run the command.
pub fn run(args: &LinCovArgs) -> Result<()> {
    let (cfg, dir) = load::resolve(&args.scenario, load::Base::CurrentDir)?.into_parts();
    let cfg = load::apply_overrides(cfg, &args.sets)?;
    let scenario = load::build(cfg, &dir)?;
    let kinds = parse_filters(&args.filter, &scenario)?;
    if let Some(runs) = args.compare_mc
        && !(1..=MAX_COMPARE_RUNS).contains(&runs)
    {
        bail!("--compare-mc {runs}: the Monte Carlo needs 1..={MAX_COMPARE_RUNS} runs");
    }
    let options = LinCovOptions {
        second_order_mean: args.second_order_mean,
    };
    let analysed = analyse(&scenario, &kinds, &args.scenario, options)?;
    let mc = match args.compare_mc {
        Some(runs) => {
            let started = Instant::now();
            let report = with_threads(args.threads, || {
                let mut opts = McOptions::new(runs, args.seed);
                opts.pcrlb = false;
                Ok(run_trade(&scenario, &kinds, &opts, &|_| {})?)
            })?;
            Some((report, started.elapsed().as_secs_f64()))
        }
        None => None,
    };
    let value = to_json(&scenario, &analysed, mc.as_ref());
    let to_stdout = args.json.as_deref().is_some_and(|p| p.as_os_str() == "-");
    if !to_stdout {
        print_table(&scenario, &analysed, mc.as_ref());
    }
    if let Some(dir) = &args.csv_dir {
        std::fs::create_dir_all(dir).with_context(|| format!("--csv-dir {}", dir.display()))?;
        for a in &analysed {
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
            crate::atomic_file::write(path, text)?;
            println!("wrote {}", path.display());
        }
    }
    Ok(())
}

fn parse_filters(list: &str, scenario: &Scenario) -> Result<Vec<FilterKind>> {
    let kinds = FilterKind::parse_list(list, &scenario.onboard)
        .with_context(|| format!("--filter '{list}'"))?;
    if kinds.is_empty() {
        bail!(
            "--filter '{list}': name at least one filter (LinCov supports: ekf, ukf, ci, dcifaif)"
        );
    }
    Ok(kinds)
}

/// The Monte Carlo summary's per-state and pos/vel RMSE keys, predicted.
fn rmse_map(l: &EntryLinCov, at: impl Fn(&[f64]) -> f64, pos: f64, vel: f64) -> Map<String, Value> {
    let mut m = Map::new();
    for (i, name) in l.states.iter().enumerate() {
        let v = at(&l.epochs.iter().map(|e| e.rmse[i]).collect::<Vec<_>>());
        m.insert(name.clone(), finite(v));
    }
    m.insert("pos_m".into(), finite(pos));
    m.insert("vel_mps".into(), finite(vel));
    m
}

/// The NEES/dof share of a mean error, time average and final
/// ([`EntryLinCovEpoch::nees_of_mean`]): LinCov's own with
/// `mc = None`, else the Monte Carlo's mean error per epoch scored in LinCov's onboard
/// covariance, over the epochs both have. A share the Monte Carlo has and LinCov does not is a
/// second-order mean error (docs/results.md, CI on orbiters-3).
pub(crate) fn mean_error_nees(l: &EntryLinCov, mc: Option<&FilterReport>) -> (f64, f64) {
    let mut vals = Vec::with_capacity(l.epochs.len());
    let mut j = 0;
    for e in &l.epochs {
        let v = match mc {
            None => e.nees_of_mean(&e.mean_error),
            Some(f) => {
                let s = &f.series;
                while j < s.times_s.len() && s.times_s[j] < e.t - 1e-6 {
                    j += 1;
                }
                if j == s.times_s.len() || (s.times_s[j] - e.t).abs() > 1e-6 {
                    continue;
                }
                let m: Vec<f64> = s.bias[j].iter().map(|v| v.unwrap_or(f64::NAN)).collect();
                e.nees_of_mean(&m)
            }
        };
        vals.push(v.unwrap_or(f64::NAN));
    }
    let avg = vals.iter().sum::<f64>() / vals.len() as f64;
    let last = match (mc, l.epochs.last()) {
        (None, _) => vals.last().copied(),
        (Some(f), Some(e)) => f
            .series
            .times_s
            .last()
            .filter(|t| (*t - e.t).abs() <= 1e-6)
            .and(vals.last().copied()),
        _ => None,
    };
    (avg, last.unwrap_or(f64::NAN))
}

fn finite(v: f64) -> Value {
    if v.is_finite() { json!(v) } else { Value::Null }
}

pub(crate) fn to_json(
    scenario: &Scenario,
    analysed: &[Analysed],
    mc: Option<&(TradeReport, f64)>,
) -> Value {
    let mean = |v: &[f64]| v.iter().sum::<f64>() / v.len().max(1) as f64;
    let last = |v: &[f64]| v.last().copied().unwrap_or(f64::NAN);
    let filters: Vec<Value> = analysed
        .iter()
        .map(|a| {
            let l = &a.lincov;
            let e = |f: fn(&EntryLinCovEpoch) -> f64| (l.time_avg(f), l.final_value(f));
            let (pos, pos_f) = e(|x| x.pos_m);
            let (vel, vel_f) = e(|x| x.vel_mps);
            let (ps, ps_f) = e(|x| x.pos_sigma_m);
            let (vs, vs_f) = e(|x| x.vel_sigma_mps);
            let dof = l.epochs.last().map_or(0, |x| x.nees_dof);
            let (bias, bias_f) = mean_error_nees(l, None);
            json!({
                "name": l.filter,
                "epochs": l.epochs.len(),
                "rmse_time_avg": rmse_map(l, mean, pos, vel),
                "rmse_final": rmse_map(l, last, pos_f, vel_f),
                "sigma_time_avg": {"pos_m": finite(ps), "vel_mps": finite(vs)},
                "sigma_final": {"pos_m": finite(ps_f), "vel_mps": finite(vs_f)},
                "anees": finite(l.time_avg(|x| x.nees)),
                "nees_dof": dof,
                "anees_kinematic": finite(l.time_avg(|x| x.nees_kinematic)),
                "nees_ratio_time_avg": finite(l.nees_ratio_time_avg()),
                "nees_ratio_final": finite(l.final_value(EntryLinCovEpoch::nees_per_dof)),
                "mean_error_nees_ratio_time_avg": finite(bias),
                "mean_error_nees_ratio_final": finite(bias_f),
                "parameters": l.parameters,
                "notes": l.notes,
                "wall_s": a.seconds,
            })
        })
        .collect();
    let mut top = json!({
        "lincov": {
            "scenario": scenario.config.name,
            "states": analysed.first().map(|a| a.lincov.states.clone()).unwrap_or_default(),
            "filters": filters,
        }
    });
    if let Some((report, seconds)) = mc {
        let per: Vec<Value> = report
            .filters
            .iter()
            .map(|f| {
                let c = &f.consistency;
                let bias = analysed
                    .iter()
                    .find(|a| a.lincov.filter == f.name)
                    .map(|a| mean_error_nees(&a.lincov, Some(f)));
                json!({
                    "name": f.name,
                    "mean_error_nees_ratio_time_avg": bias.map(|b| finite(b.0)),
                    "mean_error_nees_ratio_final": bias.map(|b| finite(b.1)),
                    "rmse_time_avg": f.rmse_time_avg,
                    "rmse_final": f.rmse_final,
                    "anees": c.anees,
                    "nees_dof": c.nees_dof,
                    "failed": f.failed,
                    "diverged": f.diverged,
                })
            })
            .collect();
        top["monte_carlo"] = json!({"runs": report.runs, "wall_s": seconds, "filters": per});
    }
    top
}

/// A table row: label, time-average and final prediction, the Monte Carlo's two.
type Row<'a> = (&'a str, f64, f64, Option<f64>, Option<f64>);

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
        let mc_get = |m: Option<&BTreeMap<String, Option<f64>>>, k: &str| {
            m.and_then(|m| m.get(k).copied().flatten())
        };
        println!(
            "  {:<24} {:>12} {:>12} {:>12} {:>12}",
            "", "time-avg", "final", "MC time-avg", "MC final"
        );
        let bias = mean_error_nees(l, None);
        let mc_bias = mc_f.map(|f| mean_error_nees(l, Some(f)));
        let rows: [Row; 6] = [
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
        ];
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

pub(crate) fn write_csv<W: std::io::Write>(
    w: &mut csv::Writer<W>,
    l: &EntryLinCov,
) -> csv::Result<()> {
    let mut header = vec![
        "t_s".to_string(),
        "pos_rmse_m".into(),
        "vel_rmse_mps".into(),
        "pos_sigma_m".into(),
        "vel_sigma_mps".into(),
        "nees".into(),
        "nees_dof".into(),
    ];
    for s in &l.states {
        header.push(format!("rmse_{s}"));
        header.push(format!("sigma_{s}"));
        header.push(format!("mean_error_{s}"));
    }
    w.write_record(&header)?;
    for e in &l.epochs {
        let mut row = vec![
            e.t.to_string(),
            e.pos_m.to_string(),
            e.vel_mps.to_string(),
            e.pos_sigma_m.to_string(),
            e.vel_sigma_mps.to_string(),
            e.nees.to_string(),
            e.nees_dof.to_string(),
        ];
        for i in 0..l.states.len() {
            row.push(e.rmse[i].to_string());
            row.push(e.sigma[i].to_string());
            row.push(e.mean_error[i].to_string());
        }
        w.write_record(&row)?;
    }
    w.flush()?;
    Ok(())
}
