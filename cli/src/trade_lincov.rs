//! `trade --method lincov|both`: the trade's statistics predicted by LinCov of each filter
//! (`entrynav::sim::lincov`) instead of, or beside, the Monte Carlo.
//!
//! `lincov` writes what `entrynav lincov` writes (JSON under `lincov`, `lincov_<filter>.csv`
//! series). `both` flies the Monte Carlo as usual and adds, per filter and headline figure
//! (time-averaged and final position and velocity RMSE, every state's time-averaged RMSE,
//! ANEES/dof), LinCov's prediction, the ratio LinCov / Monte Carlo and a flag where the two differ
//! by more than the Monte Carlo's 95 % sampling interval (RMSE: the Gaussian bound RMSE/√(2N);
//! ANEES: ANEES·√(2/(dof·N))) — where they do, the filter or the truth is nonlinear enough on
//! the dispersed runs for LinCov's first-order prediction to miss. The JSON summary carries the
//! comparison under `lincov`.

use crate::compare_stats::{Z95, se_anees, se_rmse_bound};
use crate::lincov::{Analysed, analyse, mean_error_nees, print_table, to_json, write_csv};
use anyhow::{Context, Result};
use clap::ValueEnum;
use entrynav::estimation::chi_square::chi_square_quantile;
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::Scenario;
use entrynav::sim::lincov::LinCovOptions;
use entrynav::sim::{FilterReport, TradeReport};
use serde_json::{Value, json};
use std::path::Path;

/// How `trade` computes its statistics.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum, Default)]
pub enum Method {
    /// Monte Carlo of `--runs` dispersed runs.
    #[default]
    Mc,
    /// LinCov of each filter along the nominal trajectory (one pass, no runs).
    Lincov,
    /// Both, with LinCov / Monte Carlo for every headline figure.
    Both,
}

/// `trade --method lincov`: LinCov of `filters` on `scenario`; `--json` and `--csv-dir` as
/// `entrynav lincov` writes them (files first).
pub fn run_lincov(
    scenario: &Scenario,
    filters: &[FilterKind],
    json_path: Option<&Path>,
    csv_dir: Option<&Path>,
) -> Result<()> {
    let analysed = first_order(scenario, filters)?;
    let value = to_json(scenario, &analysed, None);
    let to_stdout = json_path.is_some_and(|p| p.as_os_str() == "-");
    let mut notes = Vec::new();
    if let Some(dir) = csv_dir {
        std::fs::create_dir_all(dir).with_context(|| format!("--csv-dir {}", dir.display()))?;
        for a in &analysed {
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
            crate::atomic_file::write(path, text)?;
            notes.push(format!("wrote {}", path.display()));
        }
    }
    if !to_stdout {
        print_table(scenario, &analysed, None);
        for n in notes {
            println!("{n}");
        }
    }
    Ok(())
}

/// The first-order LinCov of `filters` (a trade's LinCov has no second-order option).
fn first_order(scenario: &Scenario, filters: &[FilterKind]) -> Result<Vec<Analysed>> {
    analyse(
        scenario,
        filters,
        &scenario.config.name,
        LinCovOptions::default(),
    )
}

/// One compared figure.
struct Row {
    figure: String,
    lincov: f64,
    mc: f64,
    /// Half-width of the Monte Carlo's 95 % interval.
    half: f64,
}

impl Row {
    fn ratio(&self) -> f64 {
        self.lincov / self.mc
    }

    fn disagrees(&self) -> bool {
        (self.lincov - self.mc).abs() > self.half
    }

    fn json(&self) -> Value {
        let f = |v: f64| if v.is_finite() { json!(v) } else { Value::Null };
        json!({
            "figure": self.figure,
            "lincov": f(self.lincov),
            "monte_carlo": f(self.mc),
            "ratio": f(self.ratio()),
            "mc_interval_95": [f(self.mc - self.half), f(self.mc + self.half)],
            "outside_mc_interval": self.disagrees(),
        })
    }
}

/// The rows of one filter: headline figures first, then every state's time-averaged RMSE.
fn rows(a: &Analysed, f: &FilterReport) -> Vec<Row> {
    let l = &a.lincov;
    let n = f.runs.saturating_sub(f.failed);
    let mut out = Vec::new();
    let mut rmse = |figure: String, lincov: f64, mc: Option<f64>| {
        if let Some(mc) = mc.filter(|m| m.is_finite() && *m > 0.0)
            && lincov.is_finite()
        {
            let half = Z95 * se_rmse_bound(mc, n);
            out.push(Row {
                figure,
                lincov,
                mc,
                half,
            });
        }
    };
    let get =
        |m: &std::collections::BTreeMap<String, Option<f64>>, k: &str| m.get(k).copied().flatten();
    rmse(
        "rmse_time_avg.pos_m".into(),
        l.time_avg(|e| e.pos_m),
        get(&f.rmse_time_avg, "pos_m"),
    );
    rmse(
        "rmse_final.pos_m".into(),
        l.final_value(|e| e.pos_m),
        get(&f.rmse_final, "pos_m"),
    );
    rmse(
        "rmse_time_avg.vel_mps".into(),
        l.time_avg(|e| e.vel_mps),
        get(&f.rmse_time_avg, "vel_mps"),
    );
    rmse(
        "rmse_final.vel_mps".into(),
        l.final_value(|e| e.vel_mps),
        get(&f.rmse_final, "vel_mps"),
    );
    for (i, name) in l.states.iter().enumerate() {
        rmse(
            format!("rmse_time_avg.{name}"),
            l.time_avg(|e| e.rmse[i]),
            get(&f.rmse_time_avg, name),
        );
    }
    let c = &f.consistency;
    if let Some(anees) = c.anees {
        let dof = c.nees_dof.max(1) as f64;
        out.push(Row {
            figure: "anees_per_dof".into(),
            lincov: l.nees_ratio_time_avg(),
            mc: anees / dof,
            half: Z95 * se_anees(anees, dof, n) / dof,
        });
        // The NEES/dof a mean error carries, q = m̄ᵀP⁻¹m̄/dof in LinCov's P. With the Monte
        // Carlo's m̂ = m̄ + ε, ε ~ N(0, Σ/n) and P⁻¹Σ ≈ c·I (c = ANEES/dof), its estimate is
        // q + 2m̄ᵀP⁻¹ε/dof + εᵀP⁻¹ε/dof: standard deviation ≈ 2√(q·c/n) from the first term and
        // a noise floor whose 95 % point is χ²₀.₉₅(dof)/dof · c/n from the second. The interval
        // is ±(Z₉₅ of the first + the floor's 95 % point), taken symmetric.
        let (q, _) = mean_error_nees(l, None);
        let (q_mc, _) = mean_error_nees(l, Some(f));
        if q.is_finite() && q_mc.is_finite() && n > 0 {
            let per_dof = anees / dof / n as f64;
            let floor = chi_square_quantile(0.95, c.nees_dof.max(1)) / dof * per_dof;
            out.push(Row {
                figure: "mean_error_nees_per_dof".into(),
                lincov: q,
                mc: q_mc,
                half: 2.0 * Z95 * (q_mc.max(0.0) * per_dof).sqrt() + floor,
            });
        }
    }
    out
}

/// LinCov beside a finished Monte Carlo: the JSON block (`lincov` in the summary) and the table.
pub struct Comparison {
    analysed: Vec<Analysed>,
    json: Value,
}

impl Comparison {
    /// LinCov of the report's filters on `scenario`, compared with `report`.
    pub fn of(scenario: &Scenario, filters: &[FilterKind], report: &TradeReport) -> Result<Self> {
        let analysed = first_order(scenario, filters)?;
        let mut json = to_json(scenario, &analysed, None)["lincov"].take();
        let per: Vec<Value> = analysed
            .iter()
            .filter_map(|a| {
                let f = report.filters.iter().find(|f| f.name == a.lincov.filter)?;
                let rows: Vec<Value> = rows(a, f).iter().map(Row::json).collect();
                Some(json!({"name": f.name, "runs": f.runs, "figures": rows}))
            })
            .collect();
        json["versus_monte_carlo"] = json!(per);
        Ok(Comparison { analysed, json })
    }

    /// LinCov's RMSE curves per metric (every state, `pos_m`, `vel_mps`), dashed and named
    /// "<filter> LinCov", for the RMSE charts of `--plots` and `--report`.
    pub fn curves(&self) -> crate::plots::ExtraCurves {
        let mut out = crate::plots::ExtraCurves::new();
        for a in &self.analysed {
            let l = &a.lincov;
            let name = format!("{} LinCov", l.filter);
            let series = |f: &dyn Fn(&entrynav::sim::lincov::EntryLinCovEpoch) -> f64| {
                l.epochs.iter().map(|e| (e.t, f(e))).collect::<Vec<_>>()
            };
            let mut add = |metric: &str, points: Vec<(f64, f64)>| {
                out.entry(metric.to_string())
                    .or_default()
                    .push(crate::plot::Curve {
                        name: name.clone(),
                        points,
                        dashed: true,
                    });
            };
            add("pos_m", series(&|e| e.pos_m));
            add("vel_mps", series(&|e| e.vel_mps));
            for (i, state) in l.states.iter().enumerate() {
                add(state, series(&|e| e.rmse[i]));
            }
        }
        out
    }

    /// The `lincov` block of the summary.
    pub fn json(&self) -> &Value {
        &self.json
    }

    /// Print LinCov / Monte Carlo per filter, flagging figures outside the Monte Carlo's interval.
    pub fn print(&self, report: &TradeReport) {
        println!(
            "\nLinCov beside the Monte Carlo (ratio = LinCov / MC; ! = outside the MC's 95 % interval)"
        );
        for a in &self.analysed {
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
            let rows = rows(a, f);
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
            let off: Vec<&str> = rows
                .iter()
                .filter(|r| r.disagrees())
                .map(|r| r.figure.as_str())
                .collect();
            if !off.is_empty() {
                println!(
                    "  warning: LinCov and the Monte Carlo disagree beyond the sampling interval on \
                     {} of {} figures ({}): the dispersed runs leave the region where the \
                     first-order (linear) prediction holds",
                    off.len(),
                    rows.len(),
                    off.join(", ")
                );
            }
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
