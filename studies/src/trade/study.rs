//! A trade study: the Monte Carlo of the filters on the scenario (new, or continuing an
//! interrupted one), handing partial results to the caller's checkpoint and stopping when the
//! caller's cancel flag is set; LinCov beside it (`method = both`) and the delivery table of a
//! scenario with `[guidance]`. `method = lincov` is LinCov alone ([`run_trade_lincov`]).

use crate::error::chain;
use crate::error::{StudyError, StudyResult};
use crate::guidance::deliver::delivery_of_study;
use crate::lincov::study::LinCovStudy;
use crate::progress::{Progress, Step};
use crate::provenance::{Provenance, Summary, Timing};
use crate::threads::with_threads;
use crate::trade::lincov_comparison::{LinCovComparison, first_order};
use crate::trade::options::{Method, TradeMode, TradeOptions};
use crate::trade::resume::resume_checksum;
use crate::trade::setup::TradeSetup;
use entrynav::sim::guided::delivery::DeliveryReport;
use entrynav::sim::monte_carlo::shard::fold_partial;
use entrynav::sim::{Checkpoint, McOptions, ShardResult, TradeReport, merge_shards, run_study};
use serde::Serialize;
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// What a trade study returns.
pub struct TradeOutcome {
    /// The statistics (`complete: false` when it was cancelled: the runs finished so far).
    pub report: TradeReport,
    /// A cancelled study's block sums, which its summary keeps for resuming it.
    pub partial: Option<ShardResult>,
    /// `method = both`: LinCov beside the Monte Carlo (a complete study only).
    pub lincov: Option<LinCovComparison>,
    /// A scenario with `[guidance]`: delivery at deployment (a complete study only).
    pub delivery: Option<DeliveryReport>,
    /// Wall time of the Monte Carlo \[s\].
    pub wall_s: f64,
    /// What went wrong beside the statistics (no delivery table), without `warning: `.
    pub warnings: Vec<String>,
}

impl TradeOutcome {
    /// The summary document (what `trade --json` writes), by `Serialize`.
    pub fn summary<'a>(&'a self, provenance: &'a Provenance) -> Summary<'a> {
        summary(
            provenance,
            &self.report,
            self.partial.as_ref(),
            self.wall_s,
            (
                self.lincov.as_ref().map(LinCovComparison::json),
                self.delivery.as_ref(),
            ),
        )
    }

    /// The summary as `trade --json` writes it: pretty JSON and a line break.
    pub fn to_json(&self, provenance: &Provenance) -> StudyResult<String> {
        pretty(&self.summary(provenance))
    }

    /// The error a cancelled study ends in once its partial results are out.
    pub fn interruption(&self) -> Option<StudyError> {
        let r = &self.report;
        (!r.complete).then(|| {
            StudyError::Interrupted(format!(
                "{} of {} runs completed (complete: false in the summary)",
                r.runs_completed, r.runs
            ))
        })
    }
}

/// A trade summary: provenance, the statistics, the optional blocks (`lincov`, `delivery`),
/// the `resume` block and its checksum when `resume` is given, then the wall-clock `timing`.
pub fn summary<'a>(
    provenance: &'a Provenance,
    report: &'a TradeReport,
    resume: Option<&'a ShardResult>,
    wall_s: f64,
    (lincov, delivery): (Option<&'a serde_json::Value>, Option<&'a DeliveryReport>),
) -> Summary<'a> {
    Summary {
        provenance,
        report,
        resume,
        resume_checksum: resume.map(resume_checksum),
        lincov,
        delivery,
        timing: Timing::of(report, wall_s),
    }
}

/// `value` as pretty JSON and a line break (how every summary file is written).
pub fn pretty(value: &impl Serialize) -> StudyResult<String> {
    serde_json::to_string_pretty(value)
        .map(|t| t + "\n")
        .map_err(|e| StudyError::Failed(format!("cannot write the JSON: {e}")))
}

/// The partial summary of a running study (a checkpoint): its text and the runs it holds.
pub fn partial_summary(
    provenance: &Provenance,
    partial: &ShardResult,
    wall_s: f64,
) -> StudyResult<(String, usize)> {
    let report = fold_partial(partial.clone())?;
    let text = pretty(&summary(
        provenance,
        &report,
        Some(partial),
        wall_s,
        (None, None),
    ))?;
    Ok((text, report.runs_completed))
}

/// Run the study of `setup` (or continue the cancelled one in `previous`), handing partial
/// results to `checkpoint` and stopping when `cancel` is set: a cancelled study's report folds
/// the finished runs and keeps their block sums.
pub fn run_trade_study(
    setup: &TradeSetup,
    options: &TradeOptions,
    previous: Option<ShardResult>,
    checkpoint: &mut (dyn Checkpoint + Send),
    cancel: Option<&'static AtomicBool>,
    progress: Progress,
) -> StudyResult<TradeOutcome> {
    options.validate()?;
    options.check_mode(TradeMode::Study {
        resume: previous.is_some(),
    })?;
    if options.method == Method::Lincov {
        return Err(options.refuse("a Monte Carlo study", "use run_trade_lincov"));
    }
    let clock = Instant::now();
    let opts = McOptions {
        pcrlb: options.pcrlb,
        cancel,
        ..McOptions::new(setup.runs, options.seed)
    };
    let label = setup.label(options);
    let total = setup.runs as u64;
    let step = |done: usize| progress(Step::of("runs", &label, done as u64, total));
    let (scenario, filters) = (&setup.scenario, &setup.filters);
    let study = with_threads(options.threads, || {
        Ok(run_study(
            scenario, filters, &opts, previous, &step, checkpoint,
        )?)
    })?;
    let (report, partial) = if study.complete {
        (merge_shards(vec![study])?, None)
    } else {
        (fold_partial(study.clone())?, Some(study))
    };
    let wall_s = clock.elapsed().as_secs_f64();
    let lincov = (options.method == Method::Both && report.complete)
        .then(|| LinCovComparison::of(scenario, filters, &report))
        .transpose()?;
    // A scenario with `[guidance]`: the same runs flown with each filter in the guidance loop.
    // A failure here never costs the Monte Carlo's results: it is a warning.
    let mut warnings = Vec::new();
    let delivery = (report.complete && scenario.config.guidance.is_some())
        .then(|| delivery_of_study(scenario, filters, setup.runs, options.seed, options.threads))
        .and_then(|d| {
            d.map_err(|e| warnings.push(format!("no delivery table: {}", chain(&e))))
                .ok()
        });
    Ok(TradeOutcome {
        report,
        partial,
        lincov,
        delivery,
        wall_s,
        warnings,
    })
}

/// `method = lincov`: LinCov of the filters along the nominal trajectory instead of the Monte
/// Carlo (what `entrynav lincov` computes, first order).
pub fn run_trade_lincov(setup: &TradeSetup, options: &TradeOptions) -> StudyResult<LinCovStudy> {
    options.validate()?;
    options.check_mode(TradeMode::Study { resume: false })?;
    Ok(LinCovStudy {
        analysed: first_order(&setup.scenario, &setup.filters)?,
        monte_carlo: None,
    })
}
