//! The entry points of a trade study: [`run_trade`] (the whole study), [`run_shard`] (a slice of
//! its blocks), [`run_study`] (the single-process study with checkpoints) and [`resume_shard`]
//! (a cancelled study continued to exactly the uninterrupted result).

use super::blocks::run_blocks;
use super::checkpoint::{Checkpoint, NoCheckpoint};
use super::options::McOptions;
use super::shard::{
    BlockSums, SHARD_FORMAT, Shard, ShardResult, fold_partial, merge_shards, scenario_fingerprint,
};
use super::state_names::state_names;
use super::trade_error::TradeError;
use super::trade_report::TradeReport;
use crate::estimation::nav::FilterKind;
use crate::scenario::Scenario;
use crate::sim::engine::channel_names;
use std::sync::Arc;

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
        channels: channel_names(scenario),
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
