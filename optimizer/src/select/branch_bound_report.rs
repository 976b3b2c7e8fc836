//! What a branch-and-bound search ([`super::branch_bound`]) is asked and what it proves: its
//! options, the progress it reports, its report and proof status.

use super::report::Selection;
use std::time::Duration;

/// The certified gap at or below which an answer is called optimal, on the criterion's scale
/// ([`SelectionProblem::tolerance`](super::SelectionProblem::tolerance)): above the accuracy of the node relaxations and far above
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

/// Options of [`SelectionProblem::branch_and_bound`](super::SelectionProblem::branch_and_bound).
#[derive(Debug, Clone, PartialEq)]
pub struct BranchBoundOptions {
    /// Close a node when its bound exceeds the incumbent by at most this, on the criterion's
    /// scale ([`SelectionProblem::tolerance`](super::SelectionProblem::tolerance)).
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
    /// criterion's scale ([`SelectionProblem::tolerance`](super::SelectionProblem::tolerance)).
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
