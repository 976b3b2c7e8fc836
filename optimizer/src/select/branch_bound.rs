//! Certified optimal k-subsets: branch and bound over site inclusion `z_i ∈ {0, 1}` on the
//! relaxation of the [parent module](super) (D- and E-optimal, with the side constraints).
//!
//! **Search.** Nodes (`node.rs`) are kept in a best-bound-first queue (ties: the
//! deeper, then the older node). Each round takes a *batch* of `batch` nodes — first the node of
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

use super::node::{Node, Outcome};
use super::*;
use rayon::prelude::*;
use std::cmp::Ordering;
use std::collections::BinaryHeap;
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

/// Make `s` the incumbent if it is strictly better (earlier candidates win ties).
fn offer(best: &mut Option<Selection>, s: Selection, updates: &mut usize) {
    if best.as_ref().is_none_or(|b| s.value > b.value) {
        *best = Some(s);
        *updates += 1;
    }
}

/// A queued node ordered by bound, then depth, then age.
struct Queued(Node);

impl PartialEq for Queued {
    fn eq(&self, other: &Self) -> bool {
        self.cmp(other) == Ordering::Equal
    }
}
impl Eq for Queued {}
impl PartialOrd for Queued {
    fn partial_cmp(&self, other: &Self) -> Option<Ordering> {
        Some(self.cmp(other))
    }
}
impl Ord for Queued {
    fn cmp(&self, other: &Self) -> Ordering {
        self.0
            .bound
            .total_cmp(&other.0.bound)
            .then(self.0.depth.cmp(&other.0.depth))
            .then(other.0.seq.cmp(&self.0.seq))
    }
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
        if !(opts.gap.is_finite() && opts.gap >= 0.0) || opts.batch == 0 {
            return Err(OptimizerError::InvalidInput(format!(
                "branch and bound needs a finite gap ≥ 0 (got {}) and a batch of at least 1",
                opts.gap
            )));
        }
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
        let initial_value = best.as_ref().map_or(f64::NEG_INFINITY, |b| b.value);
        let mut r = BranchBoundReport {
            best: Selection {
                indices: Vec::new(),
                value: f64::NEG_INFINITY,
            },
            bound: f64::INFINITY,
            gap: f64::INFINITY,
            proof_tolerance: 0.0,
            status: ProofStatus::Optimal,
            root_bound: f64::INFINITY,
            initial_value,
            nodes: 0,
            solver_calls: 0,
            solver_trouble: 0,
            pruned_cheap: 0,
            pruned_relaxation: 0,
            pruned_queued: 0,
            screened: 0,
            leaves: 0,
            infeasible: 0,
            branched: 0,
            open: 0,
            max_depth: 0,
            incumbent_updates: 0,
            evaluations,
            elapsed_s: 0.0,
        };
        let mut queue: BinaryHeap<Queued> = BinaryHeap::new();
        let mut dive: Option<Node> = Some(Node::root(self.candidates()));
        let mut seq = 0u64;
        // Largest bound of a closed node (each was within `tol` of the incumbent of its time).
        let mut closed = f64::NEG_INFINITY;
        let value = |b: &Option<Selection>| b.as_ref().map_or(f64::NEG_INFINITY, |s| s.value);
        let stopped = loop {
            let inc = value(&best);
            let tol = self.tolerance(opts.gap, inc);
            let open_bound = queue
                .peek()
                .map(|q| q.0.bound)
                .into_iter()
                .chain(dive.as_ref().map(|d| d.bound))
                .fold(f64::NEG_INFINITY, f64::max);
            progress(&BranchBoundProgress {
                nodes: r.nodes,
                open: queue.len() + usize::from(dive.is_some()),
                incumbent: inc,
                bound: inc.max(closed).max(open_bound),
                elapsed_s: started.elapsed().as_secs_f64(),
            });
            let mut batch: Vec<Node> = Vec::with_capacity(opts.batch);
            if let Some(d) = dive.take() {
                if d.bound > inc + tol {
                    batch.push(d);
                } else {
                    closed = closed.max(d.bound);
                    r.pruned_queued += 1;
                }
            }
            while batch.len() < opts.batch {
                let Some(Queued(n)) = queue.pop() else { break };
                if n.bound > inc + tol {
                    batch.push(n);
                } else {
                    closed = closed.max(n.bound);
                    r.pruned_queued += 1;
                }
            }
            if batch.is_empty() {
                break None;
            }
            // The limits are checked between batches; the first batch (the root) always runs, so
            // the bound is finite.
            if r.nodes > 0 && opts.time_limit.is_some_and(|t| started.elapsed() >= t) {
                queue.extend(batch.into_iter().map(Queued));
                break Some(ProofStatus::TimeLimit);
            }
            if r.nodes > 0 && opts.node_limit.is_some_and(|n| r.nodes >= n) {
                queue.extend(batch.into_iter().map(Queued));
                break Some(ProofStatus::NodeLimit);
            }
            let outcomes: Vec<_> = batch
                .par_iter()
                .map(|n| self.evaluate_node(n, inc, tol, opts.screening))
                .collect();
            for (slot, (node, ev)) in batch.iter().zip(outcomes).enumerate() {
                let ev = ev?;
                r.nodes += 1;
                closed = closed.max(ev.screened_bound);
                r.screened += ev.screened.len();
                r.solver_calls += ev.solver_calls;
                r.solver_trouble += ev.solver_trouble;
                r.evaluations += ev.evaluations;
                r.max_depth = r.max_depth.max(node.depth);
                match ev.outcome {
                    Outcome::Infeasible => r.infeasible += 1,
                    Outcome::Leaf(s) => {
                        r.leaves += 1;
                        offer(&mut best, s, &mut r.incumbent_updates);
                    }
                    Outcome::Pruned { bound, by_solver } => {
                        if node.depth == 0 {
                            r.root_bound = bound;
                        }
                        closed = closed.max(bound);
                        if by_solver {
                            r.pruned_relaxation += 1;
                        } else {
                            r.pruned_cheap += 1;
                        }
                    }
                    Outcome::Branched {
                        bound,
                        incumbent,
                        branch,
                        dual,
                    } => {
                        if node.depth == 0 {
                            r.root_bound = bound;
                        }
                        if let Some(s) = incumbent {
                            offer(&mut best, s, &mut r.incumbent_updates);
                        }
                        let inc = value(&best);
                        if bound <= inc + self.tolerance(opts.gap, inc) {
                            closed = closed.max(bound);
                            r.pruned_relaxation += 1;
                            continue;
                        }
                        r.branched += 1;
                        let (include, exclude) =
                            self.children(node, branch, bound, &dual, &ev.screened, &mut seq);
                        queue.push(Queued(exclude));
                        match include {
                            Some(c) if opts.dives && slot == 0 => dive = Some(c),
                            Some(c) => queue.push(Queued(c)),
                            None => {}
                        }
                    }
                }
            }
        };
        let best = best.ok_or_else(|| {
            OptimizerError::Infeasible(format!(
                "no set of k = {} candidates satisfies the side constraints",
                self.k
            ))
        })?;
        let open_bound = queue
            .iter()
            .map(|q| q.0.bound)
            .chain(dive.as_ref().map(|d| d.bound))
            .fold(f64::NEG_INFINITY, f64::max);
        r.open = queue.len() + usize::from(dive.is_some());
        r.bound = best.value.max(closed).max(open_bound);
        r.gap = r.bound - best.value;
        if r.root_bound == f64::INFINITY {
            r.root_bound = r.bound;
        }
        r.proof_tolerance = self.tolerance(PROOF_GAP, best.value);
        r.status = match stopped {
            Some(s) => s,
            None if r.gap <= r.proof_tolerance => ProofStatus::Optimal,
            None => ProofStatus::Gap,
        };
        r.best = best;
        r.elapsed_s = started.elapsed().as_secs_f64();
        Ok(r)
    }
}
