//! Every optimum checked against its input design: the trade's bound (PCRLB) and a Monte Carlo
//! of one filter on both designs, with `trade compare`'s 95 % intervals, so that a design that
//! navigates worse than what the user gave is never reported as a success.
//!
//! Headline figures: time-averaged and final position RMSE \[m\] (lower is better) and the
//! filter's ANEES/dof (closer to 1 is better; worse when it leaves the χ² band of the runs).
//! A figure is *worse* when the optimum's RMSE is higher by more than the Monte Carlo noise (the
//! 95 % interval of the change excludes 0), when its ANEES/dof is outside [`ANEES_BAND`] and
//! further from 1 than the input's, or when more runs fail; the verdict names every worse figure
//! and the objective that produced the design, and `optimize` then ends with exit code 1 after
//! writing its files.

use anyhow::Result;
use clap::Args;
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::Scenario;
use entrynav::sim::{FilterReport, McOptions, TradeReport, run_trade};
use entrynav_studies::statistics::{Difference, Estimate, se_anees, se_rmse_bound};
use serde_json::{Value, json};

/// The ANEES/dof range a consistent filter stays in on a check (the acceptance band).
pub const ANEES_BAND: [f64; 2] = [0.7, 1.5];

/// Options of the check (flattened into every `optimize` problem).
#[derive(Args, Clone, Debug)]
pub struct CheckArgs {
    /// Monte Carlo runs of the check of the optimum against the input design (each design; 10
    /// to 100000).
    #[arg(long, default_value_t = 200, allow_hyphen_values = true, value_parser = crate::args::check_runs)]
    pub check_runs: usize,
    /// Filter flown in the check (any the scenario supports).
    #[arg(long, default_value = "ekf")]
    pub check_filter: String,
    /// Master seed of the check's runs (both designs fly the same truths).
    #[arg(long, default_value_t = 1)]
    pub check_seed: u64,
    /// Skip the check (the optimum is then reported unchecked).
    #[arg(long)]
    pub no_check: bool,
}

/// The headline figures of one design.
#[derive(Debug, Clone)]
pub struct Figures {
    report: FilterReport,
    pcrlb_avg: Option<f64>,
    pcrlb_final: Option<f64>,
}

impl Figures {
    fn of(trade: &TradeReport) -> Figures {
        let bound = trade.pcrlb.as_ref().filter(|b| b.available);
        let get = |m: Option<&std::collections::BTreeMap<String, Option<f64>>>| {
            m.and_then(|m| m.get("pos_m").copied().flatten())
        };
        Figures {
            report: trade.filters[0].clone(),
            pcrlb_avg: get(bound.map(|b| &b.time_avg)),
            pcrlb_final: get(bound.map(|b| &b.final_)),
        }
    }

    fn rmse_avg(&self) -> Option<f64> {
        self.report.rmse_time_avg.get("pos_m").copied().flatten()
    }

    fn rmse_final(&self) -> Option<f64> {
        self.report.rmse_final.get("pos_m").copied().flatten()
    }

    fn anees_dof(&self) -> Option<f64> {
        let c = &self.report.consistency;
        c.anees.map(|a| a / c.nees_dof.max(1) as f64)
    }

    fn json(&self) -> Value {
        let c = &self.report.consistency;
        json!({
            "rmse_time_avg_pos_m": self.rmse_avg(),
            "rmse_final_pos_m": self.rmse_final(),
            "anees_per_dof": self.anees_dof(),
            "nees_in_band_frac": c.nees_in_bounds_frac,
            "pcrlb_time_avg_pos_m": self.pcrlb_avg,
            "pcrlb_final_pos_m": self.pcrlb_final,
            "failed": self.report.failed,
            "diverged": self.report.diverged,
        })
    }
}

/// The check of an optimum against its input design.
#[derive(Debug, Clone)]
pub struct DesignCheck {
    filter: String,
    runs: usize,
    seed: u64,
    objective: String,
    input: Figures,
    optimum: Figures,
    /// The headline figures on which the optimum is worse.
    pub worse: Vec<String>,
}

/// The check of the design `optimum` (a scenario configuration) against the input `input`, both
/// built with files from `dir`; `None` with `--no-check`.
pub fn check_configs(
    input: &entrynav::scenario::ScenarioConfig,
    optimum: &entrynav::scenario::ScenarioConfig,
    dir: &std::path::Path,
    objective: &str,
    args: &CheckArgs,
) -> Result<Option<DesignCheck>> {
    if args.no_check {
        return Ok(None);
    }
    let load = entrynav_loader::file_loader(dir);
    let a = Scenario::build(input.clone(), &load)?;
    let b = Scenario::build(optimum.clone(), &load)?;
    Ok(Some(check_designs(&a, &b, objective, args)?))
}

/// Print the check (or that it was skipped).
pub fn print_check(check: Option<&DesignCheck>) {
    match check {
        Some(c) => c.print(),
        None => {
            println!("check       skipped (--no-check): the optimum is not compared with the input")
        }
    }
}

/// Exit code 1 (after everything is written) when the check found the optimum worse.
pub fn verdict(check: Option<&DesignCheck>) -> Result<()> {
    match check {
        Some(c) if !c.worse.is_empty() => Err(crate::exit::Runtime(format!(
            "the optimum is worse than the input design on {} (objective {}); its files are \
             written for inspection",
            c.worse.join(", "),
            c.objective
        ))
        .into()),
        _ => Ok(()),
    }
}

/// Fly `args.check_filter` over `args.check_runs` runs of both designs (same seed: the same
/// truths where the designs share them) and compare the headline figures.
pub fn check_designs(
    input: &Scenario,
    optimum: &Scenario,
    objective: &str,
    args: &CheckArgs,
) -> Result<DesignCheck> {
    if !(10..=100_000).contains(&args.check_runs) {
        return Err(crate::exit::Usage(format!(
            "--check-runs {}: must be between 10 and 100000",
            args.check_runs
        ))
        .into());
    }
    let trade = |s: &Scenario| -> Result<TradeReport> {
        let filters = FilterKind::parse_list(&args.check_filter, &s.onboard)?;
        let filters = &filters[..1];
        let opts = McOptions::new(args.check_runs, args.check_seed);
        Ok(run_trade(s, filters, &opts, &|_| {})?)
    };
    let (a, b) = (Figures::of(&trade(input)?), Figures::of(&trade(optimum)?));
    let mut check = DesignCheck {
        filter: args.check_filter.clone(),
        runs: args.check_runs,
        seed: args.check_seed,
        objective: objective.to_string(),
        input: a,
        optimum: b,
        worse: Vec::new(),
    };
    check.worse = check.worse_figures();
    Ok(check)
}

impl DesignCheck {
    /// The headline figures on which the optimum is worse: a position RMSE higher by a
    /// significant margin (its 95 % interval excludes 0; a difference within the Monte Carlo
    /// noise is not a verdict), an ANEES/dof outside [`ANEES_BAND`] and further from 1 than the
    /// input's, or more failed and diverged runs.
    fn worse_figures(&self) -> Vec<String> {
        let (a, b) = (&self.input, &self.optimum);
        let diffs = self.differences();
        let mut worse = Vec::new();
        for (name, d) in [
            ("time-averaged position RMSE", diffs[0].1),
            ("final position RMSE", diffs[1].1),
        ] {
            if d.is_some_and(|d| d.diff > 0.0 && d.significant) {
                worse.push(name.to_string());
            }
        }
        if let (Some(x), Some(y)) = (a.anees_dof(), b.anees_dof()) {
            let outside = !(ANEES_BAND[0]..=ANEES_BAND[1]).contains(&y);
            if outside && (y.ln().abs() > x.ln().abs()) {
                worse.push("ANEES/dof".to_string());
            }
        }
        if b.report.failed + b.report.diverged > a.report.failed + a.report.diverged {
            worse.push("failed or diverged runs".to_string());
        }
        worse
    }
}

impl DesignCheck {
    fn differences(&self) -> Vec<(&'static str, Option<Difference>)> {
        let n = self.runs as u64;
        let rmse = |x: Option<f64>, y: Option<f64>| {
            Some(Difference::of(
                Estimate {
                    value: x?,
                    se: se_rmse_bound(x?, n),
                },
                Estimate {
                    value: y?,
                    se: se_rmse_bound(y?, n),
                },
            ))
        };
        let dof = self.input.report.consistency.nees_dof as f64;
        let anees = |x: Option<f64>, y: Option<f64>| {
            Some(Difference::of(
                Estimate {
                    value: x?,
                    se: se_anees(x?, dof, n),
                },
                Estimate {
                    value: y?,
                    se: se_anees(y?, dof, n),
                },
            ))
        };
        let (a, b) = (&self.input, &self.optimum);
        vec![
            ("rmse_time_avg_pos_m", rmse(a.rmse_avg(), b.rmse_avg())),
            ("rmse_final_pos_m", rmse(a.rmse_final(), b.rmse_final())),
            ("anees_per_dof", anees(a.anees_dof(), b.anees_dof())),
        ]
    }

    /// The check's table, and a warning naming every worse figure.
    pub fn print(&self) {
        println!();
        println!(
            "check       {} runs of {} (seed {}) on the input design and on the optimum, with \
             the PCRLB of each",
            self.runs, self.filter, self.seed
        );
        println!(
            "  {:<28} {:>12} {:>12} {:>11} {:>24}",
            "figure", "input", "optimum", "change", "95 % interval of change"
        );
        let f = |v: Option<f64>| v.map_or("-".into(), |v| format!("{v:.4}"));
        let diffs = self.differences();
        let (a, b) = (&self.input, &self.optimum);
        let rows = [
            (
                "pos RMSE time-avg [m]",
                a.rmse_avg(),
                b.rmse_avg(),
                diffs[0].1,
            ),
            (
                "pos RMSE final [m]",
                a.rmse_final(),
                b.rmse_final(),
                diffs[1].1,
            ),
            ("ANEES/dof", a.anees_dof(), b.anees_dof(), diffs[2].1),
            ("pos PCRLB time-avg [m]", a.pcrlb_avg, b.pcrlb_avg, None),
            ("pos PCRLB final [m]", a.pcrlb_final, b.pcrlb_final, None),
        ];
        for (name, x, y, d) in rows {
            let (change, ci) = match d {
                Some(d) => (
                    d.rel.map_or("-".into(), |r| format!("{:+.1} %", 100.0 * r)),
                    format!(
                        "[{:+.3}, {:+.3}]{}",
                        d.ci_low,
                        d.ci_high,
                        if d.significant { " *" } else { "" }
                    ),
                ),
                None => (String::new(), String::new()),
            };
            println!(
                "  {name:<28} {:>12} {:>12} {change:>11} {ci:>24}",
                f(x),
                f(y)
            );
        }
        println!("  (* the interval excludes 0; ANEES/dof band {ANEES_BAND:?})");
        if self.worse.is_empty() {
            println!(
                "  verdict: the optimum is not worse than the input on any figure (beyond the \
                 Monte Carlo noise)"
            );
        } else {
            eprintln!(
                "warning: the optimum of objective {} is WORSE than the input design on {} \
                 ({} runs of {}); do not use it as an improvement",
                self.objective,
                self.worse.join(", "),
                self.runs,
                self.filter
            );
        }
    }

    /// The `check` block of the JSON.
    pub fn json(&self) -> Value {
        let diffs: serde_json::Map<String, Value> = self
            .differences()
            .into_iter()
            .map(|(k, d)| {
                (
                    k.to_string(),
                    serde_json::to_value(d).unwrap_or(Value::Null),
                )
            })
            .collect();
        json!({
            "filter": self.filter,
            "runs": self.runs,
            "seed": self.seed,
            "input": self.input.json(),
            "optimum": self.optimum.json(),
            "difference": diffs,
            "anees_band": ANEES_BAND,
            "worse": self.worse,
            "verdict": if self.worse.is_empty() { "not worse" } else { "worse" },
        })
    }
}
