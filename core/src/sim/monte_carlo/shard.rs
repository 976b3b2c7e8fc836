//! Sharded Monte Carlo studies: a study split into contiguous accumulation blocks that run in
//! separate processes (or Dask workers) and merge into exactly the single-process statistics.

use super::metrics::FilterAccumulator;
use super::trade_error::TradeError;
use super::trade_report::TradeReport;
use crate::scenario::Scenario;
use crate::sim::bounds::pcrlb_sums::BoundSums;
use serde::Serialize;

/// Runs per accumulation block. Sums are formed per block in run order and blocks are combined
/// in block order, so a study split into shards (whole blocks) and merged gives exactly the
/// single-process statistics. Changing this constant changes results in the last bits.
pub const ACCUMULATION_BLOCK: usize = 256;

/// A slice `index` of `count` of a Monte Carlo study (contiguous accumulation blocks).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize)]
pub struct Shard {
    /// Zero-based shard index.
    pub index: usize,
    /// Number of shards.
    pub count: usize,
}

impl Shard {
    /// Parse `i/n` (0 ≤ i < n).
    pub fn parse(text: &str) -> Result<Shard, TradeError> {
        let bad = || {
            TradeError::Options(format!(
                "--shard '{text}': expected I/N with 0 <= I < N, e.g. 0/4"
            ))
        };
        let (i, n) = text.split_once('/').ok_or_else(bad)?;
        let (index, count) = (
            i.trim().parse::<usize>().map_err(|_| bad())?,
            n.trim().parse::<usize>().map_err(|_| bad())?,
        );
        if count == 0 || index >= count {
            return Err(bad());
        }
        Ok(Shard { index, count })
    }

    /// The accumulation blocks of this shard for a study of `runs` runs.
    pub fn blocks(&self, runs: usize) -> std::ops::Range<usize> {
        let n_blocks = runs.div_ceil(ACCUMULATION_BLOCK);
        (self.index * n_blocks / self.count)..((self.index + 1) * n_blocks / self.count)
    }
}

/// One accumulation block's sums, per filter.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct BlockSums {
    /// Block index.
    pub index: usize,
    /// One accumulator per filter, in the study's filter order.
    pub filters: Vec<FilterAccumulator>,
    /// The block's PCRLB sums.
    #[serde(default)]
    pub bounds: Option<BoundSums>,
}

/// The output of `trade --shard i/n`: everything `trade merge` needs to rebuild the study.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct ShardResult {
    /// Format version of this file.
    pub format: u32,
    /// Scenario name.
    pub scenario: String,
    /// Fingerprint of the full scenario (FNV-1a of its TOML), so overrides must match too.
    pub scenario_fingerprint: String,
    /// Total runs of the study.
    pub runs: usize,
    /// Master seed.
    pub seed: u64,
    /// Filter names, in order.
    pub filters: Vec<String>,
    /// State names.
    pub states: Vec<String>,
    /// Channel names.
    pub channels: Vec<String>,
    /// The truth atmosphere file and its run → profile rule ([`TradeReport::atmosphere`]).
    #[serde(default)]
    pub atmosphere: Option<crate::atmosphere::ProfileProvenance>,
    /// Which shard this is.
    pub shard: Shard,
    /// The shard's blocks, in block order.
    pub blocks: Vec<BlockSums>,
    /// `false` when the shard was cancelled: its last block may hold only a prefix of its runs,
    /// and `trade merge` refuses it.
    #[serde(default = "complete_default")]
    pub complete: bool,
}

fn complete_default() -> bool {
    true
}

/// Shard file format version.
pub const SHARD_FORMAT: u32 = 3;

/// FNV-1a 64 fingerprint of a scenario's canonical TOML.
pub fn scenario_fingerprint(scenario: &Scenario) -> String {
    format!("{:016x}", fnv1a64(scenario.config.to_toml_string().bytes()))
}

/// FNV-1a, 64 bits: the hash of fingerprints and checksums (fast, not cryptographic).
pub fn fnv1a64(bytes: impl IntoIterator<Item = u8>) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in bytes {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// Combine the shards of one study into its report. Refuses shards of different scenarios, seeds,
/// run counts, filters or shard counts, duplicates, and missing shards or blocks.
pub fn merge_shards(mut shards: Vec<ShardResult>) -> Result<TradeReport, TradeError> {
    let first = shards
        .first()
        .ok_or_else(|| TradeError::Options("no shard to merge".into()))?
        .clone();
    for s in &shards {
        if s.format != SHARD_FORMAT {
            return Err(TradeError::Options(format!(
                "shard format {} is not supported (expected {SHARD_FORMAT})",
                s.format
            )));
        }
        let what = if s.scenario != first.scenario
            || s.scenario_fingerprint != first.scenario_fingerprint
        {
            Some(format!(
                "scenario {} ({}) vs {} ({})",
                s.scenario, s.scenario_fingerprint, first.scenario, first.scenario_fingerprint
            ))
        } else if s.seed != first.seed {
            Some(format!("seed {} vs {}", s.seed, first.seed))
        } else if s.runs != first.runs {
            Some(format!("runs {} vs {}", s.runs, first.runs))
        } else if s.filters != first.filters {
            Some(format!("filters {:?} vs {:?}", s.filters, first.filters))
        } else if s.shard.count != first.shard.count {
            Some(format!(
                "shard count {} vs {}",
                s.shard.count, first.shard.count
            ))
        } else {
            None
        };
        if let Some(w) = what {
            return Err(TradeError::Options(format!(
                "cannot merge shards of different studies: {w}"
            )));
        }
        if !s.complete {
            return Err(TradeError::Options(format!(
                "shard {}/{} was interrupted; run it again",
                s.shard.index, s.shard.count
            )));
        }
    }
    shards.sort_by_key(|s| s.shard.index);
    let want: Vec<usize> = (0..first.shard.count).collect();
    let have: Vec<usize> = shards.iter().map(|s| s.shard.index).collect();
    if have != want {
        let missing: Vec<usize> = want.iter().filter(|i| !have.contains(i)).copied().collect();
        return Err(TradeError::Options(format!(
            "shards must be 0..{} exactly once; got {have:?} (missing {missing:?})",
            first.shard.count
        )));
    }
    let n_blocks = first.runs.div_ceil(ACCUMULATION_BLOCK);
    let mut fold = Fold::new(first.filters.len());
    for s in &shards {
        fold.add(s)?;
    }
    if fold.next != n_blocks {
        return Err(TradeError::Options(format!(
            "the shards hold {} of {n_blocks} blocks",
            fold.next
        )));
    }
    Ok(fold.report(first, true))
}

/// The report of the one shard `0/1` of a cancelled study: its completed runs (a prefix in run
/// order, the last block possibly partial), folded in block order. The statistics equal those of
/// a study of `runs_completed` runs.
pub fn fold_partial(shard: ShardResult) -> Result<TradeReport, TradeError> {
    if shard.shard.index != 0 {
        return Err(TradeError::Options(format!(
            "a partial study must start at shard 0, not {}/{}",
            shard.shard.index, shard.shard.count
        )));
    }
    let mut fold = Fold::new(shard.filters.len());
    fold.add(&shard)?;
    Ok(fold.report(shard, false))
}

/// Blocks folded in block order.
struct Fold {
    totals: Vec<FilterAccumulator>,
    bounds: Option<BoundSums>,
    next: usize,
}

impl Fold {
    fn new(filters: usize) -> Fold {
        Fold {
            totals: vec![FilterAccumulator::default(); filters],
            bounds: Some(BoundSums::default()),
            next: 0,
        }
    }

    fn add(&mut self, s: &ShardResult) -> Result<(), TradeError> {
        for b in &s.blocks {
            if b.index != self.next || b.filters.len() != self.totals.len() {
                return Err(TradeError::Options(format!(
                    "shard {} is incomplete or corrupt at block {}",
                    s.shard.index, self.next
                )));
            }
            for (t, a) in self.totals.iter_mut().zip(&b.filters) {
                t.merge(a);
            }
            self.bounds = match (self.bounds.take(), &b.bounds) {
                (Some(mut total), Some(block)) => {
                    total.merge(block);
                    Some(total)
                }
                _ => None,
            };
            self.next += 1;
        }
        Ok(())
    }

    fn report(self, first: ShardResult, complete: bool) -> TradeReport {
        let Fold { totals, bounds, .. } = self;
        let runs_completed = if complete {
            first.runs
        } else {
            totals.first().map_or(0, |a| a.runs as usize)
        };
        let pcrlb = bounds.map(|b| b.report(&first.states));
        let mut filters: Vec<_> = first
            .filters
            .iter()
            .zip(&totals)
            .map(|(k, a)| a.report(k, &first.states, &first.channels))
            .collect();
        if let Some(bound) = pcrlb.as_ref().filter(|b| b.available) {
            for f in &mut filters {
                f.set_efficiency(bound);
            }
        }
        TradeReport {
            scenario: first.scenario.clone(),
            runs: first.runs,
            complete,
            runs_completed,
            seed: first.seed,
            filters,
            states: first.states,
            channels: first.channels,
            pcrlb,
            atmosphere: first.atmosphere,
        }
    }
}
