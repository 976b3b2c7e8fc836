//! `entrynav lincov`: LinCov of filters along the scenario's nominal trajectory, optionally beside
//! a Monte Carlo of the same filters (`compare_mc` runs) with both wall times.

use crate::error::{StudyError, StudyResult};
use crate::lincov::analysis::{Analysed, analyse, parse_filters};
use crate::lincov::document::to_json;
use crate::options::{check_count, check_threads};
use crate::threads::with_threads;
use entrynav::scenario::Scenario;
use entrynav::sim::lincov::LinCovOptions;
use entrynav::sim::{McOptions, TradeReport, run_trade};
use serde_json::Value;
use std::time::Instant;

/// Most Monte Carlo runs `compare_mc` accepts.
pub const MAX_COMPARE_RUNS: usize = 20_000;

/// The options of a LinCov study.
#[derive(Debug, Clone)]
pub struct LinCovStudyOptions {
    /// Comma-separated filters (ekf, ukf as its EKF equivalent, ci, dcifaif).
    pub filters: String,
    /// Also run a Monte Carlo of this many runs (1 to [`MAX_COMPARE_RUNS`]).
    pub compare_mc: Option<usize>,
    /// Master seed of that Monte Carlo.
    pub seed: u64,
    /// Its worker threads (`None`: all cores).
    pub threads: Option<usize>,
    /// Carry the second-order mean drift of every filter's time update.
    pub second_order_mean: bool,
}

impl Default for LinCovStudyOptions {
    fn default() -> Self {
        LinCovStudyOptions {
            filters: "ekf".into(),
            compare_mc: None,
            seed: 1,
            threads: None,
            second_order_mean: false,
        }
    }
}

impl LinCovStudyOptions {
    /// Refuse an option outside its range, naming it.
    pub fn validate(&self) -> StudyResult<()> {
        if let Some(runs) = self.compare_mc {
            check_count("compare_mc", runs, 1, MAX_COMPARE_RUNS)?;
        }
        check_threads(self.threads)?;
        crate::options::filter_list("filters", &self.filters)?;
        Ok(())
    }
}

/// The result: each filter's prediction and, with `compare_mc`, the Monte Carlo's report and
/// wall time.
pub struct LinCovStudy {
    /// The predictions, in the order of the filters.
    pub analysed: Vec<Analysed>,
    /// The Monte Carlo beside them and its wall time \[s\].
    pub monte_carlo: Option<(TradeReport, f64)>,
}

impl LinCovStudy {
    /// The JSON document (`entrynav lincov --json`).
    pub fn to_json(&self, scenario: &Scenario) -> Value {
        to_json(scenario, &self.analysed, self.monte_carlo.as_ref())
    }
}

/// LinCov of `options.filters` on `scenario` (named `label` in errors), and the Monte Carlo
/// beside it when asked.
pub fn run_lincov(
    scenario: &Scenario,
    label: &str,
    options: &LinCovStudyOptions,
) -> StudyResult<LinCovStudy> {
    let kinds = parse_filters(&options.filters, scenario)?;
    options.validate()?;
    let lincov_options = LinCovOptions {
        second_order_mean: options.second_order_mean,
    };
    let analysed = analyse(scenario, &kinds, label, lincov_options)?;
    let monte_carlo = match options.compare_mc {
        Some(runs) => {
            let started = Instant::now();
            let report = with_threads(options.threads, || {
                let mut opts = McOptions::new(runs, options.seed);
                opts.pcrlb = false;
                run_trade(scenario, &kinds, &opts, &|_| {}).map_err(StudyError::from)
            })?;
            Some((report, started.elapsed().as_secs_f64()))
        }
        None => None,
    };
    Ok(LinCovStudy {
        analysed,
        monte_carlo,
    })
}
