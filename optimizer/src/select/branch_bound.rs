//! Certified optimal k-subsets: branch and bound over site inclusion `z_i ∈ {0, 1}` on the
//! relaxation of the [parent module](super) (D- and E-optimal, with the side constraints).
//!
//! **Search** (its state in `search_tree.rs`). Nodes (`node.rs`) are kept in a best-bound-first
//! queue (ties: the deeper, then the older node). Each round takes a *batch* of `batch` nodes — first the node of
//! the current depth-first *dive* (the "choose j" child of the previous round's first node, so a
//! dive runs from a best node down to a leaf in at most k rounds), then the best queued nodes —
//! evaluates them in parallel on rayon's pool and folds the outcomes **in batch order**: the
//! incumbent is updated, nodes whose bound is within `gap` of the incumbent are closed, the rest
//! are split. Because the batch is fixed by the state before it and folded in a fixed order, the
//! node count, the answer and the bound are the same on any number of threads; only the stop at
//! a time limit depends on speed.
//!
//! **Bounds.** Every bound is a dual bound of [`super::bounds`], valid whatever the
//! solver's accuracy; the same dual points screen out sites that cannot be part of a better
//! answer (reduced-cost fixing), which is what keeps the node programs small. The incumbent
//! starts as the better of the caller's selection and the swap-improved greedy one; every split
//! node adds its rounded, swap-improved selection.
//!
//! **Result** ([`ProofStatus`](super::ProofStatus), separate from errors as clarabel separates its `SolverStatus`
//! from setup errors): `Optimal` when the queue is exhausted and the certified gap
//! `bound − value` is at most [`PROOF_GAP`](super::PROOF_GAP); `Gap` when it is exhausted with a looser requested
//! gap; `TimeLimit` / `NodeLimit` when stopped early, with the gap certified at that point.

use super::branch_bound_report::{BranchBoundOptions, BranchBoundProgress, BranchBoundReport};
use super::criterion::SelectionCriterion;
use super::problem::SelectionProblem;
use super::report::Selection;
use super::search_tree::SearchTree;
use crate::error::OptimizerError;
use std::time::Instant;

impl SelectionProblem {
    /// The absolute gap that `gap` means at the value `value`: D-optimal, `gap` itself (ln det is
    /// already a log scale: a gap of 1e-6 is a relative 1e-6 in det F); E-optimal, `gap · |value|`
    /// (relative to λ_min, whose size depends on the units and the epochs).
    pub fn tolerance(&self, gap: f64, value: f64) -> f64 {
        match self.criterion {
            SelectionCriterion::LogDet => gap,
            SelectionCriterion::MinEig if value.is_finite() => gap * value.abs(),
            SelectionCriterion::MinEig => 0.0,
        }
    }

    /// Branch and bound for the best admissible k-subset (module docs). `start` (a k-subset,
    /// e.g. the heuristic answer of [`SelectionProblem::solve`]) seeds the incumbent; `progress`
    /// is called on the calling thread after every batch.
    ///
    /// Errors: invalid options or `start`, a clarabel setup failure, or no admissible k-subset.
    pub fn branch_and_bound(
        &self,
        opts: &BranchBoundOptions,
        start: Option<&Selection>,
        progress: &dyn Fn(&BranchBoundProgress),
    ) -> Result<BranchBoundReport, OptimizerError> {
        let started = Instant::now();
        check_options(opts)?;
        let (incumbent, evaluations) = self.first_incumbent(start)?;
        let mut tree = SearchTree::new(self, opts, incumbent, evaluations);
        let stopped = loop {
            progress(&tree.progress(started));
            let batch = tree.take_batch();
            if batch.is_empty() {
                break None;
            }
            // The limits are checked between batches; the first batch (the root) always runs, so
            // the bound is finite.
            if let Some(limit) = tree.limit_reached(started) {
                tree.requeue(batch);
                break Some(limit);
            }
            tree.evaluate_batch(batch)?;
        };
        tree.finish(stopped, started)
    }

    /// The first incumbent: the better of the caller's `start` (checked: an admissible set of
    /// k candidates) and the swap-improved greedy selection; with the criterion evaluations
    /// spent.
    fn first_incumbent(
        &self,
        start: Option<&Selection>,
    ) -> Result<(Option<Selection>, usize), OptimizerError> {
        let mut best: Option<Selection> = None;
        if let Some(s) = start {
            let mut idx = s.indices.clone();
            idx.sort_unstable();
            idx.dedup();
            if idx.len() != self.k
                || idx.iter().any(|&i| i >= self.candidates())
                || !self.admissible(&idx)
            {
                return Err(OptimizerError::InvalidInput(format!(
                    "the starting selection {:?} is not an admissible set of k = {} candidates",
                    s.indices, self.k
                )));
            }
            best = Some(self.selection(idx));
        }
        let (greedy, mut evaluations) = self.greedy();
        if let Some(g) = greedy {
            let (g, e) = self.swap_improve(&g);
            evaluations += e;
            if best.as_ref().is_none_or(|b| g.value > b.value) {
                best = Some(g);
            }
        }
        Ok((best, evaluations))
    }
}

/// Options the search cannot run with: a gap that is negative or not finite, an empty batch.
fn check_options(opts: &BranchBoundOptions) -> Result<(), OptimizerError> {
    if !(opts.gap.is_finite() && opts.gap >= 0.0) || opts.batch == 0 {
        return Err(OptimizerError::InvalidInput(format!(
            "branch and bound needs a finite gap ≥ 0 (got {}) and a batch of at least 1",
            opts.gap
        )));
    }
    Ok(())
}
