//! Monte Carlo engine: dispersions, truth, measurements and every filter of a trade, per run.
//!
//! Reproducibility (the nyx-space pattern): run `i` draws everything — truth dispersions,
//! atmosphere perturbation, measurement noise, filter start — from one generator seeded by
//! `run_seed(seed, i)`, so a run does not depend on which thread executes it. Runs execute in
//! fixed-size chunks in parallel (rayon) and their records are folded into the accumulators in
//! run-index order, so 1 or N threads give bit-identical statistics, and memory is bounded by the
//! chunk size, not the number of runs.

use super::checkpoint::{Checkpoint, NoCheckpoint};
use super::metrics::FilterAccumulator;
use super::pcrlb::{BoundRun, bound_run};
use super::pcrlb_sums::{BoundSums, PcrlbReport};
pub use super::record::{RecordedRun, record_run};
use super::record::{RunError, record_run_sharing};
use super::report::FilterReport;
use super::run_record::RunRecord;
pub use super::run_record::filter_run;
use super::shard::{
    ACCUMULATION_BLOCK, BlockSums, SHARD_FORMAT, Shard, ShardResult, fold_partial, merge_shards,
    scenario_fingerprint,
};
use super::shared_truth::SharedTruth;
use crate::estimation::nav::{FilterKind, NavError};
use crate::scenario::Scenario;
use rayon::prelude::*;
use serde::Serialize;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use thiserror::Error;

/// Why a trade study could not run.
#[derive(Debug, Error)]
pub enum TradeError {
    /// Filter selection problem.
    #[error(transparent)]
    Nav(#[from] NavError),
    /// The truth simulation failed (a scenario problem, reported with the run).
    #[error(transparent)]
    Truth(#[from] RunError),
    /// Bad options or shard files.
    #[error("{0}")]
    Options(String),
    /// The scenario gives the filters nothing to measure: every statistic would be empty.
    #[error(
        "scenario '{scenario}' has no measurement channel (no [sensors], or radios without \
         [[beacons]]), so a filter has nothing to navigate with; give [sensors.imu], \
         [sensors.dynamic_pressure], [sensors.heating], or [sensors.range] / \
         [sensors.range_rate] with beacons"
    )]
    NoMeasurements {
        /// The scenario's name.
        scenario: String,
    },
}

/// Monte Carlo options.
#[derive(Debug, Clone, Copy)]
pub struct McOptions {
    /// Number of runs.
    pub runs: usize,
    /// Master seed.
    pub seed: u64,
    /// Runs per parallel chunk (memory bound; does not change results).
    pub chunk: usize,
    /// Form the scenario's PCRLB from the same truth runs ([`super::pcrlb`]; costs about one
    /// EKF's worth of work per run).
    pub pcrlb: bool,
    /// Cancellation: once this flag is set, no new run starts; the runs finished so far (the
    /// longest prefix in run order) are folded and the report says `complete: false`. The core
    /// only reads the flag; the caller sets it (the CLI from its SIGINT handler).
    pub cancel: Option<&'static AtomicBool>,
}

impl McOptions {
    fn cancelled(&self) -> bool {
        self.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
    }
}

impl McOptions {
    /// `runs` runs from `seed` with the default chunk of 64.
    pub fn new(runs: usize, seed: u64) -> Self {
        McOptions {
            runs,
            seed,
            chunk: 64,
            pcrlb: true,
            cancel: None,
        }
    }
}

/// A trade study's results.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TradeReport {
    /// Scenario name.
    pub scenario: String,
    /// Runs asked for.
    pub runs: usize,
    /// Whether every run asked for is in the statistics (`false` after a cancellation).
    pub complete: bool,
    /// Runs in the statistics: runs 0..runs_completed, folded exactly as a study of
    /// `runs_completed` runs would fold them.
    pub runs_completed: usize,
    /// Master seed.
    pub seed: u64,
    /// State names of the filter model, in state order (SI units in the suffix).
    pub states: Vec<String>,
    /// Measurement channel names, in epoch-slot order.
    pub channels: Vec<String>,
    /// One report per filter, in the order asked.
    pub filters: Vec<FilterReport>,
    /// The scenario's posterior Cramér–Rao lower bound ([`super::pcrlb`]); `None` for a study
    /// merged from shards written before the bound existed.
    pub pcrlb: Option<PcrlbReport>,
    /// The truth atmosphere file, its profile count and the run → profile rule, when the truth
    /// atmosphere is a table file (`--atmosphere-file`, a scenario `model = "table"`).
    pub atmosphere: Option<crate::atmosphere::ProfileProvenance>,
}

/// State names of a scenario's filter model.
pub fn state_names(scenario: &Scenario) -> Vec<String> {
    let fm = scenario.filter_model();
    let kin: [&str; 6] = if fm.kind.is_cartesian() {
        ["x_m", "y_m", "z_m", "vx_mps", "vy_mps", "vz_mps"]
    } else {
        [
            "r_m",
            "lon_rad",
            "lat_rad",
            "v_mps",
            "fpa_rad",
            "heading_rad",
        ]
    };
    kin.iter()
        .map(|s| s.to_string())
        .chain(fm.augmented.iter().map(|a| a.name().to_string()))
        .collect()
}

/// Run a trade: `filters` on `scenario`, `opts.runs` runs; `progress(done)` is called as runs
/// finish. When `opts.cancel` is set during the study, the report holds the runs completed so far
/// (`complete: false`).
pub fn run_trade(
    scenario: &Scenario,
    filters: &[FilterKind],
    opts: &McOptions,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<TradeReport, TradeError> {
    let shard = run_shard(
        scenario,
        filters,
        opts,
        Shard { index: 0, count: 1 },
        progress,
    )?;
    if shard.complete {
        merge_shards(vec![shard])
    } else {
        fold_partial(shard)
    }
}

/// Run one shard of a trade (a contiguous range of accumulation blocks). A cancelled shard has
/// `complete: false` and ends with the runs finished before the cancellation.
pub fn run_shard(
    scenario: &Scenario,
    filters: &[FilterKind],
    opts: &McOptions,
    shard: Shard,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<ShardResult, TradeError> {
    let mut none = NoCheckpoint;
    run_shard_from(
        scenario,
        filters,
        opts,
        shard,
        Vec::new(),
        progress,
        &mut none,
    )
}

/// Continue the cancelled single-process study `previous` (a [`ShardResult`] with
/// `complete: false`, as the CLI stores it in a partial summary): its finished blocks are kept,
/// a partial last block goes on from its next run, and the result is exactly that of an
/// uninterrupted study (accumulation is sequential in run order). Refuses a `previous` of another
/// scenario, seed, run count or filter list.
pub fn resume_shard(
    scenario: &Scenario,
    filters: &[FilterKind],
    opts: &McOptions,
    previous: ShardResult,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<ShardResult, TradeError> {
    run_study(
        scenario,
        filters,
        opts,
        Some(previous),
        progress,
        &mut NoCheckpoint,
    )
}

/// The single-process study (shard `0/1`), new or continuing the cancelled `previous` (see
/// [`resume_shard`]), handing its partial results to `checkpoint` whenever it asks for them:
/// once before the first run and then after any chunk of runs. Each partial result is a
/// `complete: false` [`ShardResult`] that [`resume_shard`] continues to exactly the
/// uninterrupted result, so a study killed outright loses at most the runs since its last
/// checkpoint.
pub fn run_study(
    scenario: &Scenario,
    filters: &[FilterKind],
    opts: &McOptions,
    previous: Option<ShardResult>,
    progress: &(dyn Fn(usize) + Sync),
    checkpoint: &mut dyn Checkpoint,
) -> Result<ShardResult, TradeError> {
    let whole = Shard { index: 0, count: 1 };
    let Some(previous) = previous else {
        return run_shard_from(
            scenario,
            filters,
            opts,
            whole,
            Vec::new(),
            progress,
            checkpoint,
        );
    };
    let names: Vec<String> = filters.iter().map(|k| k.name().to_string()).collect();
    let what = if previous.scenario_fingerprint != scenario_fingerprint(scenario) {
        Some(format!(
            "scenario {} ({}) vs {} ({})",
            previous.scenario,
            previous.scenario_fingerprint,
            scenario.config.name,
            scenario_fingerprint(scenario)
        ))
    } else if previous.seed != opts.seed {
        Some(format!("seed {} vs {}", previous.seed, opts.seed))
    } else if previous.runs != opts.runs {
        Some(format!("runs {} vs {}", previous.runs, opts.runs))
    } else if previous.filters != names {
        Some(format!("filters {:?} vs {:?}", previous.filters, names))
    } else if previous.shard != (Shard { index: 0, count: 1 }) || previous.format != SHARD_FORMAT {
        Some("not a single-process study of this version".to_string())
    } else {
        None
    };
    if let Some(w) = what {
        return Err(TradeError::Options(format!(
            "cannot resume a different study: {w}"
        )));
    }
    run_shard_from(
        scenario,
        filters,
        opts,
        previous.shard,
        previous.blocks,
        progress,
        checkpoint,
    )
}

fn run_shard_from(
    scenario: &Scenario,
    filters: &[FilterKind],
    opts: &McOptions,
    shard: Shard,
    previous: Vec<BlockSums>,
    progress: &(dyn Fn(usize) + Sync),
    checkpoint: &mut dyn Checkpoint,
) -> Result<ShardResult, TradeError> {
    if opts.runs == 0 {
        return Err(TradeError::Options("--runs must be at least 1".into()));
    }
    if shard.count == 0 || shard.index >= shard.count {
        return Err(TradeError::Options(format!(
            "shard {}/{} does not exist",
            shard.index, shard.count
        )));
    }
    if scenario.channels.is_empty() {
        return Err(TradeError::NoMeasurements {
            scenario: scenario.config.name.clone(),
        });
    }
    for f in filters {
        f.check_fits(&scenario.onboard)?;
    }
    let shared = Arc::new(scenario.clone());
    let template = ShardResult {
        format: SHARD_FORMAT,
        scenario: scenario.config.name.clone(),
        scenario_fingerprint: scenario_fingerprint(scenario),
        runs: opts.runs,
        seed: opts.seed,
        filters: filters.iter().map(|k| k.name().to_string()).collect(),
        states: state_names(scenario),
        channels: super::channel_names(scenario),
        atmosphere: scenario.truth_profiles.as_ref().map(|c| c.provenance()),
        shard,
        blocks: Vec::new(),
        complete: false,
    };
    let mut save = |blocks: &dyn Fn() -> Vec<BlockSums>| {
        if checkpoint.due() {
            checkpoint.save(&ShardResult {
                blocks: blocks(),
                ..template.clone()
            });
        }
    };
    let (blocks, complete) =
        run_blocks(&shared, filters, opts, shard, previous, progress, &mut save)?;
    Ok(ShardResult {
        blocks,
        complete,
        ..template
    })
}

/// Hands the blocks so far (built by the argument, only when a checkpoint is due) to a
/// [`Checkpoint`].
type SaveIfDue<'a> = dyn FnMut(&dyn Fn() -> Vec<BlockSums>) + 'a;

fn run_blocks(
    scenario: &Arc<Scenario>,
    filters: &[FilterKind],
    opts: &McOptions,
    shard: Shard,
    previous: Vec<BlockSums>,
    progress: &(dyn Fn(usize) + Sync),
    save: &mut SaveIfDue<'_>,
) -> Result<(Vec<BlockSums>, bool), TradeError> {
    let chunk = opts.chunk.max(1);
    save(&|| previous.clone());
    let mut out = Vec::new();
    let mut done = 0;
    let mut previous = previous.into_iter().peekable();
    // The realisation of the first run to fly, shared with every run of the same one (built
    // once, when the first block with runs to do starts).
    let mut shared: Option<SharedTruth> = None;
    let mut shared_tried = false;
    for block in shard.blocks(opts.runs) {
        if opts.cancelled() {
            return Ok((out, false));
        }
        let mut first = block * ACCUMULATION_BLOCK;
        let last = ((block + 1) * ACCUMULATION_BLOCK).min(opts.runs);
        let mut accs = vec![FilterAccumulator::default(); filters.len()];
        let mut bounds = BoundSums::new(scenario);
        // A resumed study: a finished block is kept, a partial one continues from its next run.
        if let Some(prev) = previous.next_if(|b| b.index == block) {
            let had = prev.filters.first().map_or(0, |a| a.runs as usize);
            if prev.filters.len() != filters.len() || (opts.pcrlb != prev.bounds.is_some()) {
                return Err(TradeError::Options(format!(
                    "cannot resume: block {block} was run with other filters or PCRLB setting"
                )));
            }
            done += had;
            if first + had >= last {
                out.push(prev);
                continue;
            }
            first += had;
            accs = prev.filters;
            if let Some(b) = prev.bounds {
                bounds = b;
            }
        }
        let mut cut = false;
        if !shared_tried && first < last {
            shared = SharedTruth::new(scenario, opts.seed, first, opts.pcrlb);
            shared_tried = true;
        }
        for start in (first..last).step_by(chunk) {
            let end = (start + chunk).min(last);
            // A run not started because of a cancellation is `None`; the chunk is folded up to
            // the first of them, so the statistics are those of runs 0..done in run order.
            let records: Vec<Option<Result<RunWithBound, TradeError>>> = (start..end)
                .into_par_iter()
                .map(|run| {
                    (!opts.cancelled()).then(|| {
                        let shared = shared.as_ref();
                        one_run_with_bound(scenario, filters, opts.seed, run, opts.pcrlb, shared)
                    })
                })
                .collect();
            let mut chunk_bounds = Vec::with_capacity(end - start);
            for (i, rec) in records.into_iter().enumerate() {
                let Some(rec) = rec else {
                    cut = true;
                    break;
                };
                let (runs, bound) = rec?;
                for (acc, r) in accs.iter_mut().zip(runs.iter()) {
                    acc.add(start + i, r);
                }
                chunk_bounds.extend(bound);
                done += 1;
            }
            bounds.add_runs(&chunk_bounds);
            progress(done);
            // The runs so far, as resumable blocks (built only when a checkpoint is due).
            save(&|| {
                let mut so_far = out.clone();
                so_far.push(BlockSums {
                    index: block,
                    filters: accs.clone(),
                    bounds: opts.pcrlb.then(|| bounds.clone()),
                });
                so_far
            });
            if cut || opts.cancelled() {
                cut = true;
                break;
            }
        }
        let runs_in_block = accs.first().map_or(0, |a| a.runs);
        if !cut || runs_in_block > 0 {
            out.push(BlockSums {
                index: block,
                filters: accs,
                bounds: opts.pcrlb.then_some(bounds),
            });
        }
        if cut {
            return Ok((out, false));
        }
    }
    Ok((out, true))
}

/// One run's records (one per filter) and, when asked, its PCRLB contribution.
pub type RunWithBound = (Vec<RunRecord>, Option<Arc<BoundRun>>);

/// One run: the truth recorded, each filter flown over it and, with `pcrlb`, the run's
/// contribution to the scenario's PCRLB ([`super::pcrlb`]). A run of `shared`'s realisation
/// takes its trajectory and bound instead of computing them again (`sim/shared_truth.rs`).
pub fn one_run_with_bound(
    scenario: &Arc<Scenario>,
    filters: &[FilterKind],
    seed: u64,
    run: usize,
    pcrlb: bool,
    shared: Option<&SharedTruth>,
) -> Result<RunWithBound, TradeError> {
    let rec = record_run_sharing(scenario, seed, run, shared)?;
    let bound = pcrlb.then(|| match shared {
        Some(s) => s.bound_for(scenario, &rec),
        None => Arc::new(bound_run(scenario, &rec)),
    });
    let records = filters
        .iter()
        .map(|&kind| filter_run(scenario, &scenario.onboard, &rec, kind))
        .collect();
    Ok((records, bound))
}
