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
//! **Result** ([`ProofStatus`], separate from errors as clarabel separates its `SolverStatus`
//! from setup errors): `Optimal` when the queue is exhausted and the certified gap
//! `bound − value` is at most [`PROOF_GAP`]; `Gap` when it is exhausted with a looser requested
//! gap; `TimeLimit` / `NodeLimit` when stopped early, with the gap certified at that point.

use super::search_tree::SearchTree;
use super::*;
use std::time::Duration;

/// The certified gap at or below which an answer is called optimal, on the criterion's scale
/// ([`SelectionProblem::tolerance`]): above the accuracy of the node relaxations and far above
/// floating-point rounding.
pub const PROOF_GAP: f64 = 1e-6;

/// How the search stopped.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum ProofStatus {
    /// The answer is optimal: certified gap ≤ [`PROOF_GAP`] (on the criterion's scale).
    Optimal,
    /// The search finished with the requested (looser) gap: certified gap ≤ `gap`.
    Gap,
    /// Stopped at the time limit; the certified gap is reported.
    TimeLimit,
    /// Stopped at the node limit; the certified gap is reported.
    NodeLimit,
}

impl ProofStatus {
    /// Name in reports: `optimal`, `gap`, `time-limit`, `node-limit`.
    pub fn name(self) -> &'static str {
        match self {
            ProofStatus::Optimal => "optimal",
            ProofStatus::Gap => "gap",
            ProofStatus::TimeLimit => "time-limit",
            ProofStatus::NodeLimit => "node-limit",
        }
    }
}

/// Options of [`SelectionProblem::branch_and_bound`].
#[derive(Debug, Clone, PartialEq)]
pub struct BranchBoundOptions {
    /// Close a node when its bound exceeds the incumbent by at most this, on the criterion's
    /// scale ([`SelectionProblem::tolerance`]).
    pub gap: f64,
    /// Stop after this wall time (checked between batches; the first batch always runs).
    pub time_limit: Option<Duration>,
    /// Stop after this many evaluated nodes (a speed-independent limit; checked between batches,
    /// the first batch always runs).
    pub node_limit: Option<usize>,
    /// Nodes evaluated per parallel round (the result depends on it, not on the thread count).
    pub batch: usize,
    /// Spend the first slot of every batch on a depth-first dive.
    pub dives: bool,
    /// Reduced-cost screening of free sites (off only to measure what it buys).
    pub screening: bool,
}

impl Default for BranchBoundOptions {
    fn default() -> BranchBoundOptions {
        BranchBoundOptions {
            gap: PROOF_GAP,
            time_limit: None,
            node_limit: None,
            batch: 8,
            dives: true,
            screening: true,
        }
    }
}

/// The state of the search after a batch, for a progress display.
#[derive(Debug, Clone, PartialEq)]
pub struct BranchBoundProgress {
    /// Nodes evaluated.
    pub nodes: usize,
    /// Nodes waiting.
    pub open: usize,
    /// Value of the incumbent.
    pub incumbent: f64,
    /// Upper bound on every admissible k-subset.
    pub bound: f64,
    /// Wall time so far \[s\].
    pub elapsed_s: f64,
}

/// The answer of the branch and bound and the work it took.
#[derive(Debug, Clone, PartialEq)]
pub struct BranchBoundReport {
    /// The best admissible k-subset found.
    pub best: Selection,
    /// Upper bound on every admissible k-subset.
    pub bound: f64,
    /// `bound − best.value` (≥ 0): the certified gap.
    pub gap: f64,
    /// The certified gap at or below which `best` counts as optimal: [`PROOF_GAP`] on the
    /// criterion's scale ([`SelectionProblem::tolerance`]).
    pub proof_tolerance: f64,
    /// How the search stopped.
    pub status: ProofStatus,
    /// The root relaxation's bound.
    pub root_bound: f64,
    /// Value of the incumbent before the root was split.
    pub initial_value: f64,
    /// Nodes evaluated.
    pub nodes: usize,
    /// clarabel solves.
    pub solver_calls: usize,
    /// Solves that stopped without `Solved` / `AlmostSolved` (their dual bounds stay valid).
    pub solver_trouble: usize,
    /// Nodes closed by the cheap bounds, before any solve.
    pub pruned_cheap: usize,
    /// Nodes closed by the bound of their own relaxation.
    pub pruned_relaxation: usize,
    /// Queued nodes closed before evaluation by a better incumbent.
    pub pruned_queued: usize,
    /// Sites excluded from a subtree by reduced-cost screening (summed over nodes).
    pub screened: usize,
    /// Leaves valued.
    pub leaves: usize,
    /// Nodes without an admissible completion.
    pub infeasible: usize,
    /// Nodes split.
    pub branched: usize,
    /// Nodes still open when the search stopped.
    pub open: usize,
    /// Deepest node evaluated.
    pub max_depth: usize,
    /// Improvements of the incumbent during the search.
    pub incumbent_updates: usize,
    /// Criterion evaluations of roundings, swaps and the greedy start.
    pub evaluations: usize,
    /// Wall time \[s\].
    pub elapsed_s: f64,
}

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
