//! Delivery at deployment for a sharded study (`trade --shard I/N`, then `trade merge`): each
//! shard flies the delivery runs of its own accumulation blocks ([`deliver_runs`]) and stores
//! them with the run indices ([`DeliveryShard`], in the shard file); the merge puts the runs of
//! every shard back in run order and reduces them exactly as the single-process study does
//! ([`merge_delivery_shards`]), so the merged delivery table equals the unsharded one.
//!
//! A failed run is stored as its message ([`StoredDelivery::Failed`]); read back it becomes
//! [`GuidedRunError::Stored`], counted and reported like the original failure.

use super::delivery::{
    DeliveryError, DeliveryReport, RunDeliveries, algorithm_name, deliver_run, report_of, row_names,
};
use super::deployment::Delivery;
use super::guided_run_error::GuidedRunError;
use crate::estimation::nav::FilterKind;
use crate::guidance::BankLimits;
use crate::scenario::Scenario;
use rayon::prelude::*;
use serde::{Deserialize, Serialize};
use std::sync::Arc;
use thiserror::Error;

/// One run's delivery in one row as a shard file stores it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum StoredDelivery {
    /// The flight deployed.
    Delivered(Delivery),
    /// Why it did not (the error's message).
    Failed(String),
}

/// The deliveries of some runs of a study, with what the merge checks them against.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct DeliveryShard {
    /// Scenario name.
    pub scenario: String,
    /// `apollo` or `fnpeg`.
    pub algorithm: String,
    /// Master seed of the study.
    pub seed: u64,
    /// Runs of the whole study (not of this shard).
    pub study_runs: usize,
    /// The bank limits the rate check uses.
    pub limits: BankLimits,
    /// Row names (`perfect-nav`, `unguided`, the filters).
    pub rows: Vec<String>,
    /// `(run index, one delivery per row)`, in run order.
    pub runs: Vec<(usize, Vec<StoredDelivery>)>,
}

/// Why shards' deliveries cannot be merged.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum DeliveryShardError {
    /// The study cannot be flown (no `[guidance]`, a filter that does not fit, …).
    #[error(transparent)]
    Delivery(#[from] DeliveryError),
    /// No shard was given.
    #[error("no shard with deliveries to merge")]
    Empty,
    /// Two shards belong to different studies.
    #[error(
        "shards of different delivery studies: {field} is {first} in one and {other} in another"
    )]
    Mismatch {
        /// The field that differs.
        field: &'static str,
        /// Its value in the first shard.
        first: String,
        /// Its value in the other.
        other: String,
    },
    /// A run index outside the study, or one given twice.
    #[error("run {run} is {why} (study of {runs} runs)")]
    Run {
        /// The run index.
        run: usize,
        /// `outside the study`, `in two shards`, or `in no shard`.
        why: &'static str,
        /// Runs of the study.
        runs: usize,
    },
    /// A run whose row count differs from the study's rows.
    #[error("run {run} has {got} deliveries, the study has {rows} rows")]
    Rows {
        /// The run index.
        run: usize,
        /// Deliveries stored.
        got: usize,
        /// Rows of the study.
        rows: usize,
    },
}

/// Fly the delivery runs `runs` (indices into the study of `study_runs` runs from `seed`) with
/// `filters`, in parallel, reduced in run order.
pub fn deliver_runs(
    scenario: &Scenario,
    filters: &[FilterKind],
    study_runs: usize,
    seed: u64,
    runs: std::ops::Range<usize>,
) -> Result<DeliveryShard, DeliveryShardError> {
    if study_runs == 0 || runs.end > study_runs {
        return Err(DeliveryError::Runs(study_runs).into());
    }
    let name = scenario.config.name.clone();
    let cfg = scenario
        .config
        .guidance
        .as_ref()
        .ok_or_else(|| DeliveryError::from(GuidedRunError::NoGuidance(name.clone())))?;
    let limits = scenario
        .build_guidance()
        .ok_or_else(|| GuidedRunError::NoGuidance(name.clone()))
        .and_then(|b| b.map_err(GuidedRunError::from))
        .map_err(DeliveryError::from)?
        .limits;
    for f in filters {
        f.check_fits(&scenario.onboard)
            .map_err(|e| DeliveryError::Engine(e.into()))?;
    }
    let shared = Arc::new(scenario.clone());
    let stored = runs
        .into_par_iter()
        .map(|run| {
            let row = deliver_run(&shared, filters, seed, run)
                .into_iter()
                .map(|r| match r {
                    Ok(d) => StoredDelivery::Delivered(d),
                    Err(e) => StoredDelivery::Failed(e.to_string()),
                })
                .collect();
            (run, row)
        })
        .collect();
    Ok(DeliveryShard {
        scenario: name,
        algorithm: algorithm_name(cfg.algorithm).to_string(),
        seed,
        study_runs,
        limits,
        rows: row_names(filters),
        runs: stored,
    })
}

/// Merge the deliveries of every shard of one study into its report. Refuses shards of
/// different studies, a run given twice or outside the study, and a study with runs missing.
pub fn merge_delivery_shards(
    shards: Vec<DeliveryShard>,
) -> Result<DeliveryReport, DeliveryShardError> {
    let first = shards.first().ok_or(DeliveryShardError::Empty)?.clone();
    let total = first.study_runs;
    let mut slots: Vec<Option<RunDeliveries>> = vec![None; total];
    for s in shards {
        let differs = |field, a: String, b: String| {
            (a != b).then_some(DeliveryShardError::Mismatch {
                field,
                first: a,
                other: b,
            })
        };
        if let Some(e) = [
            differs("scenario", first.scenario.clone(), s.scenario.clone()),
            differs("algorithm", first.algorithm.clone(), s.algorithm.clone()),
            differs("seed", first.seed.to_string(), s.seed.to_string()),
            differs("runs", total.to_string(), s.study_runs.to_string()),
            differs("rows", first.rows.join(","), s.rows.join(",")),
            differs(
                "bank limits",
                format!("{:?}", first.limits),
                format!("{:?}", s.limits),
            ),
        ]
        .into_iter()
        .flatten()
        .next()
        {
            return Err(e);
        }
        for (run, row) in s.runs {
            let bad = |why| DeliveryShardError::Run {
                run,
                why,
                runs: total,
            };
            let slot = slots.get_mut(run).ok_or_else(|| bad("outside the study"))?;
            if slot.is_some() {
                return Err(bad("in two shards"));
            }
            if row.len() != first.rows.len() {
                return Err(DeliveryShardError::Rows {
                    run,
                    got: row.len(),
                    rows: first.rows.len(),
                });
            }
            *slot = Some(
                row.into_iter()
                    .map(|d| match d {
                        StoredDelivery::Delivered(d) => Ok(d),
                        StoredDelivery::Failed(m) => Err(GuidedRunError::Stored(m)),
                    })
                    .collect(),
            );
        }
    }
    let per_run = slots
        .into_iter()
        .enumerate()
        .map(|(run, s)| {
            s.ok_or(DeliveryShardError::Run {
                run,
                why: "in no shard",
                runs: total,
            })
        })
        .collect::<Result<Vec<_>, _>>()?;
    Ok(report_of(
        first.scenario,
        &first.algorithm,
        first.seed,
        &first.limits,
        &first.rows,
        per_run,
    ))
}
