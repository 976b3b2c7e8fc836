//! The state of a running branch and bound ([`super::branch_bound`]): the queue of open nodes,
//! the current dive, the incumbent, the largest bound of the closed nodes and the report's
//! counters, with one method per step of a round — take a batch, evaluate it in parallel, fold
//! the outcomes in batch order — and the final report.

use super::branch_bound_report::{
    BranchBoundOptions, BranchBoundProgress, BranchBoundReport, PROOF_GAP, ProofStatus,
};
use super::node::{Evaluation, Node, Outcome};
use super::problem::SelectionProblem;
use super::report::Selection;
use crate::error::OptimizerError;
use rayon::prelude::*;
use std::cmp::Ordering;
use std::collections::BinaryHeap;
use std::time::Instant;

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

/// A running search.
pub(super) struct SearchTree<'p> {
    problem: &'p SelectionProblem,
    opts: &'p BranchBoundOptions,
    queue: BinaryHeap<Queued>,
    /// The node of the depth-first dive, evaluated first in the next batch.
    dive: Option<Node>,
    /// Creation counter of nodes.
    seq: u64,
    /// Largest bound of a closed node (each was within `tol` of the incumbent of its time).
    closed: f64,
    best: Option<Selection>,
    /// The counters; `best`, `bound`, `gap`, `status` and the rest are filled by
    /// [`SearchTree::finish`].
    report: BranchBoundReport,
}

impl<'p> SearchTree<'p> {
    /// The root alone, with the incumbent `best` found with `evaluations` criterion evaluations.
    pub fn new(
        problem: &'p SelectionProblem,
        opts: &'p BranchBoundOptions,
        best: Option<Selection>,
        evaluations: usize,
    ) -> SearchTree<'p> {
        let initial_value = best.as_ref().map_or(f64::NEG_INFINITY, |b| b.value);
        SearchTree {
            problem,
            opts,
            queue: BinaryHeap::new(),
            dive: Some(Node::root(problem.candidates())),
            seq: 0,
            closed: f64::NEG_INFINITY,
            best,
            report: BranchBoundReport::started(initial_value, evaluations),
        }
    }

    /// Value of the incumbent (−∞ without one).
    fn incumbent(&self) -> f64 {
        self.best.as_ref().map_or(f64::NEG_INFINITY, |s| s.value)
    }

    /// The gap tolerance at the current incumbent.
    fn tolerance(&self) -> f64 {
        self.problem.tolerance(self.opts.gap, self.incumbent())
    }

    /// Nodes waiting (the queue and the dive).
    fn open(&self) -> usize {
        self.queue.len() + usize::from(self.dive.is_some())
    }

    /// The state before the next batch.
    pub fn progress(&self, started: Instant) -> BranchBoundProgress {
        let inc = self.incumbent();
        let open_bound = self
            .queue
            .peek()
            .map(|q| q.0.bound)
            .into_iter()
            .chain(self.dive.as_ref().map(|d| d.bound))
            .fold(f64::NEG_INFINITY, f64::max);
        BranchBoundProgress {
            nodes: self.report.nodes,
            open: self.open(),
            incumbent: inc,
            bound: inc.max(self.closed).max(open_bound),
            elapsed_s: started.elapsed().as_secs_f64(),
        }
    }

    /// The next batch: the dive's node, then the best queued ones; nodes whose bound no longer
    /// beats the incumbent by more than the tolerance are closed on the way.
    pub fn take_batch(&mut self) -> Vec<Node> {
        let threshold = self.incumbent() + self.tolerance();
        let mut batch: Vec<Node> = Vec::with_capacity(self.opts.batch);
        if let Some(d) = self.dive.take() {
            self.admit(d, threshold, &mut batch);
        }
        while batch.len() < self.opts.batch {
            let Some(Queued(n)) = self.queue.pop() else {
                break;
            };
            self.admit(n, threshold, &mut batch);
        }
        batch
    }

    /// Put `n` into `batch` if its bound exceeds `threshold`, else close it.
    fn admit(&mut self, n: Node, threshold: f64, batch: &mut Vec<Node>) {
        if n.bound > threshold {
            batch.push(n);
        } else {
            self.closed = self.closed.max(n.bound);
            self.report.pruned_queued += 1;
        }
    }

    /// The limit that stops the search before the next batch, if any (never before the root).
    pub fn limit_reached(&self, started: Instant) -> Option<ProofStatus> {
        let nodes = self.report.nodes;
        if nodes > 0 && self.opts.time_limit.is_some_and(|t| started.elapsed() >= t) {
            return Some(ProofStatus::TimeLimit);
        }
        if nodes > 0 && self.opts.node_limit.is_some_and(|n| nodes >= n) {
            return Some(ProofStatus::NodeLimit);
        }
        None
    }

    /// Return an unevaluated batch to the queue (the search stopped at a limit).
    pub fn requeue(&mut self, batch: Vec<Node>) {
        self.queue.extend(batch.into_iter().map(Queued));
    }

    /// Evaluate `batch` in parallel against the incumbent of its start and fold the outcomes
    /// in batch order.
    pub fn evaluate_batch(&mut self, batch: Vec<Node>) -> Result<(), OptimizerError> {
        let (inc, tol) = (self.incumbent(), self.tolerance());
        let (problem, screening) = (self.problem, self.opts.screening);
        let outcomes: Vec<_> = batch
            .par_iter()
            .map(|n| problem.evaluate_node(n, inc, tol, screening))
            .collect();
        for (slot, (node, ev)) in batch.iter().zip(outcomes).enumerate() {
            self.fold(slot, node, ev?);
        }
        Ok(())
    }

    /// Count the evaluation of `node` (at position `slot` of its batch) and act on its outcome.
    fn fold(&mut self, slot: usize, node: &Node, ev: Evaluation) {
        let r = &mut self.report;
        r.nodes += 1;
        self.closed = self.closed.max(ev.screened_bound);
        r.screened += ev.screened.len();
        r.solver_calls += ev.solver_calls;
        r.solver_trouble += ev.solver_trouble;
        r.evaluations += ev.evaluations;
        r.max_depth = r.max_depth.max(node.depth);
        match ev.outcome {
            Outcome::Infeasible => r.infeasible += 1,
            Outcome::Leaf(s) => {
                r.leaves += 1;
                self.offer(s);
            }
            Outcome::Pruned { bound, by_solver } => {
                if node.depth == 0 {
                    r.root_bound = bound;
                }
                self.closed = self.closed.max(bound);
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
                    self.offer(s);
                }
                if bound <= self.incumbent() + self.tolerance() {
                    self.closed = self.closed.max(bound);
                    self.report.pruned_relaxation += 1;
                    return;
                }
                self.report.branched += 1;
                let (include, exclude) =
                    self.problem
                        .children(node, branch, bound, &dual, &ev.screened, &mut self.seq);
                self.queue.push(Queued(exclude));
                match include {
                    Some(c) if self.opts.dives && slot == 0 => self.dive = Some(c),
                    Some(c) => self.queue.push(Queued(c)),
                    None => {}
                }
            }
        }
    }

    /// Make `s` the incumbent if it is strictly better (earlier candidates win ties).
    fn offer(&mut self, s: Selection) {
        if self.best.as_ref().is_none_or(|b| s.value > b.value) {
            self.best = Some(s);
            self.report.incumbent_updates += 1;
        }
    }

    /// The report once the search stopped (`stopped`: at a limit; `None`: queue exhausted).
    /// Errors when no admissible k-subset was found.
    pub fn finish(
        self,
        stopped: Option<ProofStatus>,
        started: Instant,
    ) -> Result<BranchBoundReport, OptimizerError> {
        let open = self.open();
        let SearchTree {
            problem,
            queue,
            dive,
            closed,
            best,
            mut report,
            ..
        } = self;
        let best = best.ok_or_else(|| {
            OptimizerError::Infeasible(format!(
                "no set of k = {} candidates satisfies the side constraints",
                problem.k
            ))
        })?;
        let open_bound = queue
            .iter()
            .map(|q| q.0.bound)
            .chain(dive.as_ref().map(|d| d.bound))
            .fold(f64::NEG_INFINITY, f64::max);
        report.open = open;
        report.bound = best.value.max(closed).max(open_bound);
        report.gap = report.bound - best.value;
        if report.root_bound == f64::INFINITY {
            report.root_bound = report.bound;
        }
        report.proof_tolerance = problem.tolerance(PROOF_GAP, best.value);
        report.status = match stopped {
            Some(s) => s,
            None if report.gap <= report.proof_tolerance => ProofStatus::Optimal,
            None => ProofStatus::Gap,
        };
        report.best = best;
        report.elapsed_s = started.elapsed().as_secs_f64();
        Ok(report)
    }
}

impl BranchBoundReport {
    /// The counters of a search about to start from an incumbent of value `initial_value`.
    fn started(initial_value: f64, evaluations: usize) -> BranchBoundReport {
        BranchBoundReport {
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
        }
    }
}
