//! `entrynav guidance deliver` as a study: the Monte Carlo of delivery at deployment with
//! navigation filters in the guidance loop, against perfect navigation and the unguided
//! reference bank on the same dispersion draws (`entrynav::sim::delivery`); and the same
//! delivery for a trade of a scenario with `[guidance]` ([`delivery_of_study`]).

use crate::error::{StudyError, StudyResult, chain};
use crate::options::{MAX_RUNS, check_count, check_threads};
use crate::progress::{Progress, Step};
use crate::threads::with_threads;
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::Scenario;
use entrynav::sim::guided::Delivery;
use entrynav::sim::guided::delivery::{DeliveryReport, run_delivery};
use serde::Serialize;

/// What to fly in the loop, how often.
#[derive(Debug, Clone, PartialEq, serde::Deserialize)]
#[serde(default, deny_unknown_fields)]
pub struct DeliverOptions {
    /// Comma-separated filters flown in the loop: ekf, ukf, ci, dcifaif, mmae, mmae-moe, ukf-cm,
    /// ukf-ac, uskf-nn; `none`: perfect navigation and the unguided bank only.
    pub filters: String,
    /// Monte Carlo runs (`None`: the scenario's `monte_carlo.runs`).
    pub runs: Option<usize>,
    /// Master seed; run r draws its truth from run_seed(seed, r) as `trade` does.
    pub seed: u64,
    /// Worker threads (`None`: all cores).
    pub threads: Option<usize>,
}

impl Default for DeliverOptions {
    fn default() -> Self {
        DeliverOptions {
            filters: "ekf".into(),
            runs: None,
            seed: 1,
            threads: None,
        }
    }
}

impl DeliverOptions {
    /// Refuse an option outside its range, naming it.
    pub fn validate(&self) -> StudyResult<()> {
        if let Some(runs) = self.runs {
            check_count("runs", runs, 1, MAX_RUNS)?;
        }
        check_threads(self.threads)?;
        if !self.no_filters() {
            crate::options::filter_list("filters", &self.filters)?;
        }
        Ok(())
    }

    /// Whether `filters` is `none` (perfect navigation and the unguided bank only).
    pub fn no_filters(&self) -> bool {
        self.filters.trim() == "none"
    }
}

/// The delivery Monte Carlo's result.
#[derive(Debug, Clone)]
pub struct DeliveryStudy {
    /// The rows (each filter, perfect navigation, the unguided bank) and every run's deliveries.
    pub report: DeliveryReport,
}

/// One run's row in the JSON: its delivery or why it failed.
#[derive(Debug, Serialize)]
pub struct RunRow<'a> {
    /// The run.
    pub run: usize,
    /// The row's name.
    pub row: &'a str,
    /// The delivery, when the run delivered.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub delivery: Option<&'a Delivery>,
    /// Why it did not.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failure: Option<String>,
}

/// The JSON document (`guidance deliver --json`): the rows under `delivery`, every run's
/// deliveries under `runs`.
#[derive(Debug, Serialize)]
pub struct DeliveryDocument<'a> {
    /// The report.
    pub delivery: &'a DeliveryReport,
    /// Each run's row of each row, run by run.
    pub runs: Vec<RunRow<'a>>,
    /// What the table must say beside its numbers
    /// ([`delivery_warnings`](super::delivery_warnings::delivery_warnings)).
    pub warnings: Vec<String>,
}

impl DeliveryStudy {
    /// The JSON document, to serialise.
    pub fn document(&self) -> DeliveryDocument<'_> {
        let report = &self.report;
        let names: Vec<&str> = report.rows.iter().map(|r| r.name.as_str()).collect();
        DeliveryDocument {
            delivery: report,
            runs: report
                .per_run
                .iter()
                .enumerate()
                .flat_map(|(run, rows)| {
                    rows.iter().zip(names.clone()).map(move |(r, name)| RunRow {
                        run,
                        row: name,
                        delivery: r.as_ref().ok(),
                        failure: r.as_ref().err().map(ToString::to_string),
                    })
                })
                .collect(),
            warnings: super::delivery_warnings::delivery_warnings(report),
        }
    }
}

/// The delivery Monte Carlo of `options.filters` on `scenario`, reporting finished runs.
pub fn run_deliver(
    scenario: &Scenario,
    options: &DeliverOptions,
    progress: Progress<'_>,
) -> StudyResult<DeliveryStudy> {
    options.validate()?;
    let filters = if options.no_filters() {
        Vec::new()
    } else {
        crate::filters::fitting_filters("filters", &options.filters, &scenario.onboard)?
    };
    let runs = options.runs.unwrap_or(scenario.config.monte_carlo.runs);
    let report = with_threads(options.threads, || {
        let progress = |done: usize| progress(Step::of("runs", "", done as u64, runs as u64));
        run_delivery(scenario, &filters, runs, options.seed, &progress)
            .map_err(|e| StudyError::Refused(e.to_string()))
    })?;
    Ok(DeliveryStudy { report })
}

/// `trade` on a scenario with `[guidance]`: the delivery Monte Carlo of the study's filters on
/// the same run seeds (`run_seed(seed, r)`, the trade's truths), on `threads` workers.
pub fn delivery_of_study(
    scenario: &Scenario,
    filters: &[FilterKind],
    runs: usize,
    seed: u64,
    threads: Option<usize>,
) -> StudyResult<DeliveryReport> {
    with_threads(threads, || {
        run_delivery(scenario, filters, runs, seed, &|_| {}).map_err(|e| {
            StudyError::Failed(format!(
                "the delivery at deployment of the study's filters in the guidance loop: {}",
                chain(&e)
            ))
        })
    })
}
