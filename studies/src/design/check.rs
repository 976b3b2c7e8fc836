//! Every optimum checked against its input design: the trade's bound (PCRLB) and a Monte Carlo
//! of one filter on both designs, with `trade compare`'s 95 % intervals, so that a design that
//! navigates worse than what the user gave is never reported as a success.
//!
//! Headline figures: time-averaged and final position RMSE \[m\] (lower is better) and the
//! filter's ANEES/dof (closer to 1 is better; worse when it leaves the χ² band of the runs).
//! A figure is *worse* when the optimum's RMSE is higher by more than the Monte Carlo noise (the
//! 95 % interval of the change excludes 0), when its ANEES/dof is outside [`ANEES_BAND`] and
//! further from 1 than the input's, or when more runs fail; the verdict names every worse figure
//! and the objective that produced the design, and [`verdict`] turns it into the error a front
//! end ends with (the command line: exit code 1, after writing its files).

use crate::error::{StudyError, StudyResult};
use crate::options::check_count;
use crate::statistics::{Difference, Estimate, se_anees, se_rmse_bound};
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav::sim::{FilterReport, McOptions, TradeReport, run_trade};
use serde_json::{Value, json};
use std::collections::BTreeMap;
use std::path::Path;

/// The ANEES/dof range a consistent filter stays in on a check (the acceptance band).
pub const ANEES_BAND: [f64; 2] = [0.7, 1.5];

/// Fewest Monte Carlo runs of a check (fewer give intervals too wide to judge anything).
pub const MIN_CHECK_RUNS: usize = 10;
/// Most Monte Carlo runs of a check, per design (100 000 runs of a filter are minutes to hours).
pub const MAX_CHECK_RUNS: usize = 100_000;

/// How a design study checks its answer (the `check_*` options of each study).
#[derive(Debug, Clone, Copy)]
pub struct CheckSettings<'a> {
    /// Monte Carlo runs of each design.
    pub runs: usize,
    /// Filter flown (the first of a list).
    pub filter: &'a str,
    /// Master seed of the runs (both designs fly the same truths).
    pub seed: u64,
}

/// Refuse `check_runs` outside [`MIN_CHECK_RUNS`]..=[`MAX_CHECK_RUNS`] unless the check is
/// skipped.
pub fn validate_check(check_runs: usize, no_check: bool) -> StudyResult<()> {
    if !no_check {
        check_count("check_runs", check_runs, MIN_CHECK_RUNS, MAX_CHECK_RUNS)?;
    }
    Ok(())
}

/// The options every design shares, refused by name: the filter its LinCov objectives score,
/// the filter and run count of its check, and the name of the scenario it writes.
pub fn validate_shared(
    lincov_filter: &str,
    (check_filter, check_runs, no_check): (&str, usize, bool),
    scenario_name: Option<&str>,
) -> StudyResult<()> {
    crate::options::filter("lincov_filter", lincov_filter)?;
    crate::options::filter("check_filter", check_filter)?;
    if let Some(n) = scenario_name {
        crate::options::name("scenario_name", n)?;
    }
    validate_check(check_runs, no_check)
}

/// The headline figures of one design.
#[derive(Debug, Clone)]
pub struct Figures {
    /// The filter's Monte Carlo report.
    pub report: FilterReport,
    /// Time-averaged position PCRLB \[m\], when the trade had one.
    pub pcrlb_avg: Option<f64>,
    /// Final position PCRLB \[m\].
    pub pcrlb_final: Option<f64>,
}

impl Figures {
    fn of(trade: &TradeReport) -> Figures {
        let bound = trade.pcrlb.as_ref().filter(|b| b.available);
        let get = |m: Option<&BTreeMap<String, Option<f64>>>| {
            m.and_then(|m| m.get("pos_m").copied().flatten())
        };
        Figures {
            report: trade.filters[0].clone(),
            pcrlb_avg: get(bound.map(|b| &b.time_avg)),
            pcrlb_final: get(bound.map(|b| &b.final_)),
        }
    }

    /// Time-averaged position RMSE \[m\].
    pub fn rmse_avg(&self) -> Option<f64> {
        self.report.rmse_time_avg.get("pos_m").copied().flatten()
    }

    /// Final position RMSE \[m\].
    pub fn rmse_final(&self) -> Option<f64> {
        self.report.rmse_final.get("pos_m").copied().flatten()
    }

    /// ANEES per degree of freedom.
    pub fn anees_dof(&self) -> Option<f64> {
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
    /// The filter flown.
    pub filter: String,
    /// Runs per design.
    pub runs: usize,
    /// Their master seed.
    pub seed: u64,
    /// The objective that produced the optimum.
    pub objective: String,
    /// The input design's figures.
    pub input: Figures,
    /// The optimum's figures.
    pub optimum: Figures,
    /// The headline figures on which the optimum is worse.
    pub worse: Vec<String>,
}

/// The check of the design `optimum` (a scenario configuration) against the input `input`, both
/// built with files from `dir`; `None` when `settings` is `None` (the check skipped).
pub fn check_configs(
    input: &ScenarioConfig,
    optimum: &ScenarioConfig,
    dir: &Path,
    objective: &str,
    settings: Option<CheckSettings<'_>>,
) -> StudyResult<Option<DesignCheck>> {
    let Some(settings) = settings else {
        return Ok(None);
    };
    let load = entrynav_loader::file_loader(dir);
    let a = Scenario::build(input.clone(), &load)?;
    let b = Scenario::build(optimum.clone(), &load)?;
    Ok(Some(check_designs(&a, &b, objective, settings)?))
}

/// Fly the check's filter over its runs on both designs (same seed: the same truths where the
/// designs share them) and compare the headline figures.
pub fn check_designs(
    input: &Scenario,
    optimum: &Scenario,
    objective: &str,
    settings: CheckSettings<'_>,
) -> StudyResult<DesignCheck> {
    validate_check(settings.runs, false)?;
    let trade = |s: &Scenario| -> StudyResult<TradeReport> {
        let filters = crate::filters::fitting_filters("check_filter", settings.filter, &s.onboard)?;
        let opts = McOptions::new(settings.runs, settings.seed);
        Ok(run_trade(s, &filters[..1], &opts, &|_| {})?)
    };
    let (a, b) = (Figures::of(&trade(input)?), Figures::of(&trade(optimum)?));
    let mut check = DesignCheck {
        filter: settings.filter.to_string(),
        runs: settings.runs,
        seed: settings.seed,
        objective: objective.to_string(),
        input: a,
        optimum: b,
        worse: Vec::new(),
    };
    check.worse = check.worse_figures();
    Ok(check)
}

/// The error a front end ends with (after writing its files) when `check` found the optimum
/// worse.
pub fn verdict(check: Option<&DesignCheck>) -> StudyResult<()> {
    match check {
        Some(c) if !c.worse.is_empty() => Err(StudyError::Failed(format!(
            "the optimum is worse than the input design on {} (objective {}); its files are \
             written for inspection",
            c.worse.join(", "),
            c.objective
        ))),
        _ => Ok(()),
    }
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

    /// The changes of the time-averaged and final position RMSE and of ANEES/dof, input to
    /// optimum, with their 95 % intervals (by their JSON keys).
    pub fn differences(&self) -> Vec<(&'static str, Option<Difference>)> {
        let n = self.runs as u64;
        let rmse = |x: Option<f64>, y: Option<f64>| {
            let e = |v: f64| Estimate {
                value: v,
                se: se_rmse_bound(v, n),
            };
            Some(Difference::of(e(x?), e(y?)))
        };
        let dof = self.input.report.consistency.nees_dof as f64;
        let anees = |x: Option<f64>, y: Option<f64>| {
            let e = |v: f64| Estimate {
                value: v,
                se: se_anees(v, dof, n),
            };
            Some(Difference::of(e(x?), e(y?)))
        };
        let (a, b) = (&self.input, &self.optimum);
        vec![
            ("rmse_time_avg_pos_m", rmse(a.rmse_avg(), b.rmse_avg())),
            ("rmse_final_pos_m", rmse(a.rmse_final(), b.rmse_final())),
            ("anees_per_dof", anees(a.anees_dof(), b.anees_dof())),
        ]
    }

    /// The warning naming every worse figure, if any.
    pub fn warning(&self) -> Option<String> {
        (!self.worse.is_empty()).then(|| {
            format!(
                "the optimum of objective {} is WORSE than the input design on {} ({} runs of \
                 {}); do not use it as an improvement",
                self.objective,
                self.worse.join(", "),
                self.runs,
                self.filter
            )
        })
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
