//! Monte Carlo engine: dispersions, truth, measurements and every filter of a trade, per run.
//!
//! Reproducibility (the nyx-space pattern): run `i` draws everything — truth dispersions,
//! atmosphere perturbation, measurement noise, filter start — from one generator seeded by
//! `run_seed(seed, i)`, so a run does not depend on which thread executes it. Runs execute in
//! fixed-size chunks in parallel (rayon) and their records are folded into the accumulators in
//! run-index order, so 1 or N threads give bit-identical statistics, and memory is bounded by the
//! chunk size, not the number of runs.

use super::metrics::{EpochRecord, FilterAccumulator, FinalRecord, RunRecord};
use super::navigation::{FilterOutcome, NavStep, run_filter};
use super::report::FilterReport;
use super::{SimError, run_seed, simulate_truth};
use crate::estimation::nav::setup::estimate_spherical;
use crate::estimation::nav::{FilterKind, NavError, build_filter, filter_start};
use crate::frames::spherical_to_fixed;
use crate::math::wrap_pi;
use crate::scenario::Scenario;
use nalgebra::SVector;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use serde::Serialize;
use std::sync::Arc;
use thiserror::Error;

/// Why a trade study could not run.
#[derive(Debug, Error)]
pub enum TradeError {
    /// Filter selection problem.
    #[error(transparent)]
    Nav(#[from] NavError),
    /// The truth simulation failed (a scenario problem, reported with the run).
    #[error("run {run}: {source}")]
    Truth {
        /// Run index.
        run: usize,
        /// Cause.
        source: SimError,
    },
    /// Bad options.
    #[error("{0}")]
    Options(String),
}

/// Monte Carlo options.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct McOptions {
    /// Number of runs.
    pub runs: usize,
    /// Master seed.
    pub seed: u64,
    /// Runs per parallel chunk (memory bound; does not change results).
    pub chunk: usize,
}

impl McOptions {
    /// `runs` runs from `seed` with the default chunk of 64.
    pub fn new(runs: usize, seed: u64) -> Self {
        McOptions {
            runs,
            seed,
            chunk: 64,
        }
    }
}

/// A trade study's results.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TradeReport {
    /// Scenario name.
    pub scenario: String,
    /// Runs.
    pub runs: usize,
    /// Master seed.
    pub seed: u64,
    /// State names of the filter model, in state order (SI units in the suffix).
    pub states: Vec<String>,
    /// One report per filter, in the order asked.
    pub filters: Vec<FilterReport>,
}

/// State names of a scenario's filter model.
pub fn state_names(scenario: &Scenario) -> Vec<String> {
    let fm = &scenario.filter_model;
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
    /// Which shard this is.
    pub shard: Shard,
    /// The shard's blocks, in block order.
    pub blocks: Vec<BlockSums>,
}

/// Shard file format version.
pub const SHARD_FORMAT: u32 = 1;

/// FNV-1a 64 fingerprint of a scenario's canonical TOML.
pub fn scenario_fingerprint(scenario: &Scenario) -> String {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for b in scenario.config.to_toml_string().bytes() {
        h ^= b as u64;
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    format!("{h:016x}")
}

/// Run a trade: `filters` on `scenario`, `opts.runs` runs; `progress(done)` is called as runs finish.
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
    merge_shards(vec![shard])
}

/// Run one shard of a trade (a contiguous range of accumulation blocks).
pub fn run_shard(
    scenario: &Scenario,
    filters: &[FilterKind],
    opts: &McOptions,
    shard: Shard,
    progress: &(dyn Fn(usize) + Sync),
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
    for f in filters {
        f.check_fits(scenario)?;
    }
    let n = scenario.filter_model.state_dim();
    let shared = Arc::new(scenario.clone());
    let sc = &shared;
    let blocks = match n {
        6 => blocks_n::<6>(sc, filters, opts, shard, progress)?,
        7 => blocks_n::<7>(sc, filters, opts, shard, progress)?,
        8 => blocks_n::<8>(sc, filters, opts, shard, progress)?,
        9 => blocks_n::<9>(sc, filters, opts, shard, progress)?,
        10 => blocks_n::<10>(sc, filters, opts, shard, progress)?,
        other => return Err(NavError::Dimension(other).into()),
    };
    Ok(ShardResult {
        format: SHARD_FORMAT,
        scenario: scenario.config.name.clone(),
        scenario_fingerprint: scenario_fingerprint(scenario),
        runs: opts.runs,
        seed: opts.seed,
        filters: filters.iter().map(|k| k.name().to_string()).collect(),
        states: state_names(scenario),
        shard,
        blocks,
    })
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
    let mut totals = vec![FilterAccumulator::default(); first.filters.len()];
    let mut next = 0;
    for s in &shards {
        for b in &s.blocks {
            if b.index != next || b.filters.len() != totals.len() {
                return Err(TradeError::Options(format!(
                    "shard {} is incomplete or corrupt at block {next}",
                    s.shard.index
                )));
            }
            for (t, a) in totals.iter_mut().zip(&b.filters) {
                t.merge(a);
            }
            next += 1;
        }
    }
    if next != n_blocks {
        return Err(TradeError::Options(format!(
            "the shards hold {next} of {n_blocks} blocks"
        )));
    }
    Ok(TradeReport {
        scenario: first.scenario.clone(),
        runs: first.runs,
        seed: first.seed,
        filters: first
            .filters
            .iter()
            .zip(&totals)
            .map(|(k, a)| a.report(k, &first.states))
            .collect(),
        states: first.states,
    })
}

fn blocks_n<const N: usize>(
    scenario: &Arc<Scenario>,
    filters: &[FilterKind],
    opts: &McOptions,
    shard: Shard,
    progress: &(dyn Fn(usize) + Sync),
) -> Result<Vec<BlockSums>, TradeError> {
    let chunk = opts.chunk.max(1);
    let mut out = Vec::new();
    let mut done = 0;
    for block in shard.blocks(opts.runs) {
        let first = block * ACCUMULATION_BLOCK;
        let last = ((block + 1) * ACCUMULATION_BLOCK).min(opts.runs);
        let mut accs = vec![FilterAccumulator::default(); filters.len()];
        for start in (first..last).step_by(chunk) {
            let end = (start + chunk).min(last);
            let records: Vec<Result<Vec<RunRecord>, TradeError>> = (start..end)
                .into_par_iter()
                .map(|run| one_run::<N>(scenario, filters, opts.seed, run))
                .collect();
            for (i, rec) in records.into_iter().enumerate() {
                for (acc, r) in accs.iter_mut().zip(rec?.iter()) {
                    acc.add(start + i, r);
                }
                done += 1;
            }
            progress(done);
        }
        out.push(BlockSums {
            index: block,
            filters: accs,
        });
    }
    Ok(out)
}

/// Everything for one run: truth, measurements and each filter's records.
pub fn one_run<const N: usize>(
    scenario: &Arc<Scenario>,
    filters: &[FilterKind],
    seed: u64,
    run: usize,
) -> Result<Vec<RunRecord>, TradeError> {
    let mut rng = ChaCha8Rng::seed_from_u64(run_seed(seed, run as u64));
    let draw = scenario.draw_truth(&mut rng);
    let truth = simulate_truth(scenario, &draw, &mut rng)
        .map_err(|source| TradeError::Truth { run, source })?;
    let start = filter_start::<N>(scenario, &draw, &truth.samples[0], &mut rng);
    let mut out = Vec::with_capacity(filters.len());
    for kind in filters {
        let mut rec = RunRecord {
            epochs: Vec::new(),
            times: Vec::new(),
            final_: None,
            failure: None,
            filter_ns: 0,
            steps: 0,
        };
        let mut last: Option<NavStep<N>> = None;
        match build_filter::<N>(*kind, scenario, &start) {
            Err(e) => rec.failure = Some((0.0, e.to_string())),
            Ok(mut filter) => {
                let summary = run_filter(scenario, &draw, &truth, filter.as_mut(), |step| {
                    rec.times.push(step.t);
                    rec.epochs.push(epoch_record(scenario, step));
                    last = Some(step.clone());
                });
                rec.filter_ns = summary.filter_ns;
                rec.steps = summary.steps;
                match summary.outcome {
                    FilterOutcome::Failed { t, reason } => rec.failure = Some((t, reason)),
                    FilterOutcome::Completed => {
                        if let Some(step) = &last {
                            rec.final_ = Some(FinalRecord {
                                downrange_crossrange: downrange_crossrange(scenario, step),
                            });
                        }
                    }
                }
            }
        }
        out.push(rec);
    }
    Ok(out)
}

fn epoch_record<const N: usize>(scenario: &Scenario, step: &NavStep<N>) -> EpochRecord {
    let err: Vec<f64> = step.err.iter().copied().collect();
    let sigma: Vec<f64> = (0..N).map(|i| step.p[(i, i)].max(0.0).sqrt()).collect();
    EpochRecord {
        pos_vel_err: pos_vel_error(scenario, step),
        nees: step.nees(),
        density_rel_err: step
            .density_profile_est
            .map(|d| (d - step.density_true) / step.density_true),
        density_at_estimate_rel_err: step
            .density_est
            .map(|d| (d - step.density_true) / step.density_true),
        weights: step.info.weights.clone(),
        err,
        sigma,
    }
}

fn pos_vel_error<const N: usize>(scenario: &Scenario, step: &NavStep<N>) -> (f64, f64) {
    if scenario.filter_model.kind.is_cartesian() {
        let e = &step.err;
        (
            (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt(),
            (e[3] * e[3] + e[4] * e[4] + e[5] * e[5]).sqrt(),
        )
    } else {
        let x: [f64; 6] = [
            step.x[0], step.x[1], step.x[2], step.x[3], step.x[4], step.x[5],
        ];
        let tr: [f64; 6] = [
            step.truth[0],
            step.truth[1],
            step.truth[2],
            step.truth[3],
            step.truth[4],
            step.truth[5],
        ];
        let (pe, ve) = spherical_to_fixed(&x);
        let (pt, vt) = spherical_to_fixed(&tr);
        let d = |a: [f64; 3], b: [f64; 3]| {
            ((a[0] - b[0]).powi(2) + (a[1] - b[1]).powi(2) + (a[2] - b[2]).powi(2)).sqrt()
        };
        (d(pe, pt), d(ve, vt))
    }
}

/// Downrange/crossrange position error \[m\] of the estimate at the final epoch, in the local
/// horizontal plane at the true position, downrange along the true heading.
fn downrange_crossrange<const N: usize>(scenario: &Scenario, step: &NavStep<N>) -> (f64, f64) {
    let est = estimate_spherical(
        scenario,
        &SVector::<f64, N>::from_fn(|i, _| step.x[i]),
        step.t,
    );
    let tr = step.truth_spherical;
    let dn = tr[0] * wrap_pi(est[2] - tr[2]);
    let de = tr[0] * tr[2].cos() * wrap_pi(est[1] - tr[1]);
    let (s, c) = tr[5].sin_cos();
    (dn * c + de * s, -dn * s + de * c)
}
