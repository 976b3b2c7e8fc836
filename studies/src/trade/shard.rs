//! One shard of a trade (`trade --shard I/N`, Python's `trade_shard`): the block sums of a
//! contiguous range of accumulation blocks, with the study's provenance and, for a scenario with
//! `[guidance]`, the delivery runs of those blocks — the shard file that `trade merge` combines
//! into exactly the single-process result.

use crate::error::chain;
use crate::error::{StudyError, StudyResult};
use crate::provenance::Provenance;
use crate::threads::with_threads;
use crate::trade::delivery::shard_delivery;
use crate::trade::options::{TradeMode, TradeOptions};
use crate::trade::setup::TradeSetup;
use entrynav::sim::guided::delivery_shard::DeliveryShard;
use entrynav::sim::monte_carlo::shard::ACCUMULATION_BLOCK;
use entrynav::sim::{McOptions, Shard, ShardResult, run_shard};
use std::sync::atomic::AtomicBool;
use std::time::Instant;

/// What a shard file says of its study beyond the shard's sums: the `--set` overrides and the
/// truth atmosphere source, which the merged summary's provenance keeps.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct StudyProvenance {
    /// The `--set PATH=VALUE` overrides, in the order given.
    pub overrides: Vec<String>,
    /// The truth atmosphere source ([`Provenance::atmosphere`]).
    pub atmosphere: Option<serde_json::Value>,
}

impl StudyProvenance {
    /// The part of `p` that every shard of one study shares.
    pub fn of(p: &Provenance) -> StudyProvenance {
        StudyProvenance {
            overrides: p.overrides.clone(),
            atmosphere: p.atmosphere.clone(),
        }
    }
}

/// A shard file as `trade --shard I/N --json FILE` writes it: the shard's sums and its study's
/// provenance.
#[derive(Debug, serde::Serialize)]
pub struct ShardRun {
    /// The sums.
    #[serde(flatten)]
    pub result: ShardResult,
    /// Overrides and atmosphere source.
    pub provenance: StudyProvenance,
    /// Wall time of the shard's runs \[s\] (`trade merge` reports their sum).
    pub wall_s: f64,
    /// A scenario with `[guidance]`: the delivery runs of the shard's blocks.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub delivery: Option<DeliveryShard>,
    /// Which shard of how many.
    #[serde(skip)]
    pub shard: Shard,
    /// Runs of the whole study.
    #[serde(skip)]
    pub runs: usize,
    /// A shard that holds no runs, without `note: `.
    #[serde(skip)]
    pub notes: Vec<String>,
    /// No delivery in this shard, without `warning: `.
    #[serde(skip)]
    pub warnings: Vec<String>,
}

impl ShardRun {
    /// The shard file's JSON text (compact, as `trade --shard` writes it).
    pub fn to_json(&self) -> StudyResult<String> {
        serde_json::to_string(self)
            .map_err(|e| StudyError::Failed(format!("cannot write the shard's JSON: {e}")))
    }

    /// The error of a cancelled shard, which must not be written (a shard must be complete to
    /// merge).
    pub fn interruption(&self) -> Option<StudyError> {
        (!self.result.complete).then(|| {
            StudyError::Interrupted(format!(
                "shard {}/{} not written (a shard must be complete to merge)",
                self.shard.index, self.shard.count
            ))
        })
    }
}

/// The note of a shard that holds no runs.
fn empty_shard_note(shard: Shard, runs: usize) -> Option<String> {
    let blocks = runs.div_ceil(ACCUMULATION_BLOCK);
    shard.blocks(runs).is_empty().then(|| {
        format!(
            "shard {}/{} of this {runs}-run study holds no runs: a shard holds whole accumulation \
             blocks of {ACCUMULATION_BLOCK} runs (so that merged shards equal the single-process \
             study bit for bit) and the study has {blocks}; use at most {blocks} shard(s)",
            shard.index, shard.count,
        )
    })
}

/// Run shard `shard` of the study of `setup`; stop when `cancel` is set (the shard is then
/// incomplete: [`ShardRun::interruption`]). A failed delivery is a warning, never the shard's
/// sums.
pub fn run_trade_shard(
    setup: &TradeSetup,
    options: &TradeOptions,
    shard: Shard,
    cancel: Option<&'static AtomicBool>,
) -> StudyResult<ShardRun> {
    options.validate()?;
    options.check_mode(TradeMode::Shard)?;
    let notes: Vec<String> = empty_shard_note(shard, setup.runs).into_iter().collect();
    let opts = McOptions {
        pcrlb: options.pcrlb,
        cancel,
        ..McOptions::new(setup.runs, options.seed)
    };
    let clock = Instant::now();
    let result = with_threads(options.threads, || {
        Ok(run_shard(
            &setup.scenario,
            &setup.filters,
            &opts,
            shard,
            &|_| {},
        )?)
    })?;
    let mut warnings = Vec::new();
    let delivery = (result.complete && setup.scenario.config.guidance.is_some())
        .then(|| {
            let study = (setup.runs, options.seed);
            shard_delivery(
                &setup.scenario,
                &setup.filters,
                study,
                shard,
                options.threads,
            )
        })
        .and_then(|d| {
            d.map_err(|e| warnings.push(format!("no delivery in this shard: {}", chain(&e))))
                .ok()
        });
    Ok(ShardRun {
        result,
        provenance: StudyProvenance::of(&setup.provenance(Vec::new())),
        wall_s: clock.elapsed().as_secs_f64(),
        delivery,
        shard,
        runs: setup.runs,
        notes,
        warnings,
    })
}
