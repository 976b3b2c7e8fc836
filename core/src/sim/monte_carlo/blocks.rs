//! The study's loop over its accumulation blocks: runs in parallel chunks, folded in run order
//! into each block's sums, checkpointed, cancellable, and resumable from a partial block.

use super::metrics::FilterAccumulator;
use super::one_run::{RunWithBound, one_run_with_bound};
use super::options::McOptions;
use super::shard::{ACCUMULATION_BLOCK, BlockSums, Shard};
use super::shared_truth::SharedTruth;
use super::trade_error::TradeError;
use crate::estimation::nav::FilterKind;
use crate::scenario::Scenario;
use crate::sim::bounds::pcrlb_sums::BoundSums;
use rayon::prelude::*;
use std::sync::Arc;

/// Hands the blocks so far (built by the argument, only when a checkpoint is due) to a
/// [`Checkpoint`].
pub(super) type SaveIfDue<'a> = dyn FnMut(&dyn Fn() -> Vec<BlockSums>) + 'a;

pub(super) fn run_blocks(
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
            let runs = start..end;
            let (folded, cut_here) = fold_chunk(
                scenario,
                filters,
                opts,
                shared.as_ref(),
                runs,
                &mut accs,
                &mut bounds,
            )?;
            done += folded;
            cut = cut_here;
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

/// Fly the runs `runs` in parallel and fold them in run order into `accs` and `bounds`. A run
/// not started because of a cancellation is `None`; the chunk is folded up to the first of them,
/// so the statistics are those of the runs before it in run order. Returns the number of runs
/// folded and whether a cancellation cut the chunk.
fn fold_chunk(
    scenario: &Arc<Scenario>,
    filters: &[FilterKind],
    opts: &McOptions,
    shared: Option<&SharedTruth>,
    runs: std::ops::Range<usize>,
    accs: &mut [FilterAccumulator],
    bounds: &mut BoundSums,
) -> Result<(usize, bool), TradeError> {
    let start = runs.start;
    let mut chunk_bounds = Vec::with_capacity(runs.len());
    let records: Vec<Option<Result<RunWithBound, TradeError>>> = runs
        .into_par_iter()
        .map(|run| {
            (!opts.cancelled())
                .then(|| one_run_with_bound(scenario, filters, opts.seed, run, opts.pcrlb, shared))
        })
        .collect();
    let (mut folded, mut cut) = (0, false);
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
        folded += 1;
    }
    bounds.add_runs(&chunk_bounds);
    Ok((folded, cut))
}
