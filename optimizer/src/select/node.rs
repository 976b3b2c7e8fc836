//! One branch-and-bound node (Welch 1982, "Branch-and-bound search for experimental designs
//! based on D optimality and other criteria", Technometrics 24(1); Ko, Lee & Queyranne 1995,
//! "An exact algorithm for maximum entropy sampling", Oper. Res. 43(4)): some sites fixed in,
//! some fixed out, the rest free.
//!
//! Evaluating a node is a pure function of the node, the problem and the incumbent value at the
//! start of its batch, so the search gives the same answer whichever thread evaluates it:
//!
//! 1. leaves (nothing left to choose, or exactly as many free sites as are needed) are valued;
//! 2. the cheap bounds — the parent's dual point and the trace bound of [`super::bounds`] — may
//!    prune the node without calling the solver;
//! 3. free sites whose inclusion alone cannot beat the incumbent (reduced-cost screening with the
//!    parent's dual point) are excluded from the node's subtree, shrinking the program;
//! 4. clarabel solves the node relaxation; the bound of its dual point may prune, and screening
//!    with it excludes more sites from the children;
//! 5. otherwise the top-r rounding of the relaxed weights, swap-improved inside the node, is an
//!    incumbent candidate, and the free site whose weight is closest to ½ (ties: the larger
//!    weight, then the lower index) is the branching variable.

use super::dual_point::DualPoint;
use super::problem::SelectionProblem;
use super::relaxation::Subproblem;
use super::report::Selection;
use crate::error::OptimizerError;
use clarabel::solver::SolverStatus;
use std::sync::Arc;

/// A node: `fixed` chosen (ascending), `excluded` removed (bitset), the rest free.
#[derive(Debug, Clone)]
pub(super) struct Node {
    pub fixed: Vec<usize>,
    pub excluded: Vec<u64>,
    /// A valid bound on the node's subtree (the parent's bound; +∞ at the root).
    pub bound: f64,
    /// The parent's dual point, for the cheap bound.
    pub dual: Option<Arc<DualPoint>>,
    pub depth: usize,
    /// Creation order (ties in the queue go to the older node).
    pub seq: u64,
}

/// What evaluating a node found.
#[derive(Debug, Clone)]
pub(super) enum Outcome {
    /// No admissible completion.
    Infeasible,
    /// A fully determined selection.
    Leaf(Selection),
    /// The node's bound does not beat the incumbent by more than the gap tolerance.
    Pruned { bound: f64, by_solver: bool },
    /// Split on `branch`: the node's bound, its dual point and an incumbent candidate.
    Branched {
        bound: f64,
        incumbent: Option<Selection>,
        branch: usize,
        dual: Option<Arc<DualPoint>>,
    },
}

/// An [`Outcome`] and the work it took.
#[derive(Debug, Clone)]
pub(super) struct Evaluation {
    pub outcome: Outcome,
    /// Free sites screened out (reduced-cost fixing): excluded from both children.
    pub screened: Vec<usize>,
    /// The largest bound of a subtree closed by screening (−∞ if none).
    pub screened_bound: f64,
    /// clarabel solves (0 or 1).
    pub solver_calls: usize,
    /// Solves that ended with a status other than `Solved` / `AlmostSolved`.
    pub solver_trouble: usize,
    /// Criterion evaluations of the rounding and swap.
    pub evaluations: usize,
}

impl Evaluation {
    /// No work done yet; `Infeasible` until an outcome is set.
    fn new() -> Evaluation {
        Evaluation {
            outcome: Outcome::Infeasible,
            screened: Vec::new(),
            screened_bound: f64::NEG_INFINITY,
            solver_calls: 0,
            solver_trouble: 0,
            evaluations: 0,
        }
    }

    /// The evaluation ending with `outcome`.
    fn with(mut self, outcome: Outcome) -> Evaluation {
        self.outcome = outcome;
        self
    }
}

/// The branching variable: the free site whose relaxed weight is closest to ½ (ties: the larger
/// weight, then the lower index). `free` is not empty (a node with `free.len() > r ≥ 1`).
fn branching_site(free: &[usize], z: &[f64]) -> usize {
    (0..free.len())
        .max_by(|&p, &q| {
            let frac = |v: f64| v.min(1.0 - v);
            frac(z[p])
                .total_cmp(&frac(z[q]))
                .then(z[p].total_cmp(&z[q]))
                .then(free[q].cmp(&free[p]))
        })
        .map(|p| free[p])
        .expect("a node with free.len() > r ≥ 1 has free sites")
}

pub(super) fn bit(set: &[u64], i: usize) -> bool {
    set[i / 64] >> (i % 64) & 1 == 1
}

pub(super) fn set_bit(set: &mut [u64], i: usize) {
    set[i / 64] |= 1 << (i % 64);
}

impl Node {
    /// The root: nothing fixed.
    pub fn root(m: usize) -> Node {
        Node {
            fixed: Vec::new(),
            excluded: vec![0; m.div_ceil(64)],
            bound: f64::INFINITY,
            dual: None,
            depth: 0,
            seq: 0,
        }
    }
}

impl SelectionProblem {
    /// Evaluate `node` against the incumbent value `incumbent` with gap tolerance `tol`
    /// (`screening`: apply the reduced-cost screening of [`SelectionProblem::screen`]), in the
    /// steps of the module documentation.
    pub(super) fn evaluate_node(
        &self,
        node: &Node,
        incumbent: f64,
        tol: f64,
        screening: bool,
    ) -> Result<Evaluation, OptimizerError> {
        let mut eval = Evaluation::new();
        if !self.admissible(&node.fixed) || node.fixed.len() > self.k {
            return Ok(eval);
        }
        let r = self.k - node.fixed.len();
        let mut free: Vec<usize> = (0..self.candidates())
            .filter(|&i| !bit(&node.excluded, i) && node.fixed.binary_search(&i).is_err())
            .collect();
        if let Some(outcome) = self.settled(&node.fixed, &free, r) {
            return Ok(eval.with(outcome));
        }
        let threshold = incumbent + tol;
        let mut bound = self.cheap_bound(node, &free, r);
        if bound <= threshold {
            let by_solver = false;
            return Ok(eval.with(Outcome::Pruned { bound, by_solver }));
        }
        // Screen with the parent's dual point before solving: a smaller program.
        if let Some(d) = node.dual.as_ref().filter(|_| screening) {
            self.apply_screen(d, &node.fixed, &mut free, r, threshold, &mut eval);
            if let Some(outcome) = self.settled(&node.fixed, &free, r) {
                return Ok(eval.with(outcome));
            }
        }
        let sub = Subproblem {
            fixed: &node.fixed,
            free: &free,
            r,
        };
        let raw = self.solve_subproblem(&sub)?;
        eval.solver_calls = 1;
        eval.solver_trouble = usize::from(!matches!(
            raw.status,
            SolverStatus::Solved | SolverStatus::AlmostSolved
        ));
        let dual = self.dual_from_relaxation(&sub, &raw).map(Arc::new);
        if let Some(d) = &dual {
            bound = bound.min(self.dual_bound(d, &sub));
        }
        eval.outcome = Outcome::Pruned {
            bound,
            by_solver: true,
        };
        if bound <= threshold {
            return Ok(eval);
        }
        let z_of: Vec<(usize, f64)> = free
            .iter()
            .zip(&raw.z)
            .map(|(&i, v)| (i, if v.is_finite() { *v } else { 0.0 }))
            .collect();
        if let Some(d) = dual.as_ref().filter(|_| screening) {
            self.apply_screen(d, &node.fixed, &mut free, r, threshold, &mut eval);
            if let Some(outcome) = self.settled(&node.fixed, &free, r) {
                return Ok(eval.with(outcome));
            }
        }
        // The relaxed weights of the sites still free after screening.
        let z: Vec<f64> = z_of
            .iter()
            .filter(|(i, _)| free.binary_search(i).is_ok())
            .map(|&(_, v)| v)
            .collect();
        let incumbent = self.node_incumbent(&node.fixed, &free, r, &z, &mut eval);
        let branch = branching_site(&free, &z);
        Ok(eval.with(Outcome::Branched {
            bound,
            incumbent,
            branch,
            dual,
        }))
    }

    /// The bounds that need no solve: the parent's, the trace bound and the parent's dual point.
    fn cheap_bound(&self, node: &Node, free: &[usize], r: usize) -> f64 {
        let sub = Subproblem {
            fixed: &node.fixed,
            free,
            r,
        };
        let mut bound = node.bound.min(self.trace_bound(&sub));
        if let Some(d) = &node.dual {
            bound = bound.min(self.dual_bound(d, &sub));
        }
        bound
    }

    /// The top-r rounding of the relaxed weights `z` of the `free` sites, swap-improved inside
    /// the node (the `fixed` sites stay); `None` when the side constraints stop the rounding.
    fn node_incumbent(
        &self,
        fixed: &[usize],
        free: &[usize],
        r: usize,
        z: &[f64],
        eval: &mut Evaluation,
    ) -> Option<Selection> {
        self.round_among(fixed, free, r, z).map(|s| {
            let movable: Vec<usize> = s
                .indices
                .iter()
                .filter(|i| fixed.binary_search(i).is_err())
                .copied()
                .collect();
            let (s, e) = self.swap_search(fixed, &movable, free);
            eval.evaluations = e + 1;
            s
        })
    }

    /// A node that needs no bound: nothing left to choose, too few free sites, or exactly
    /// enough (the only completion is valued).
    fn settled(&self, fixed: &[usize], free: &[usize], r: usize) -> Option<Outcome> {
        if r == 0 {
            return Some(Outcome::Leaf(self.selection(fixed.to_vec())));
        }
        if free.len() < r {
            return Some(Outcome::Infeasible);
        }
        if free.len() == r {
            let all: Vec<usize> = fixed.iter().chain(free).copied().collect();
            return Some(if self.admissible(&all) {
                Outcome::Leaf(self.selection(all))
            } else {
                Outcome::Infeasible
            });
        }
        None
    }

    /// Remove the sites `dual` screens out at `threshold` from `free` and record them.
    fn apply_screen(
        &self,
        dual: &DualPoint,
        fixed: &[usize],
        free: &mut Vec<usize>,
        r: usize,
        threshold: f64,
        eval: &mut Evaluation,
    ) {
        let sub = Subproblem { fixed, free, r };
        let (out, worst) = self.screen(dual, &sub, threshold);
        if out.is_empty() {
            return;
        }
        free.retain(|i| out.binary_search(i).is_err());
        eval.screened.extend(out);
        eval.screened.sort_unstable();
        eval.screened_bound = eval.screened_bound.max(worst);
    }

    /// The two children of `node` split on `j`: `j` chosen (sites of side constraints it fills
    /// are excluded), then `j` excluded. Both inherit `bound`, `dual` and the `screened`
    /// exclusions.
    pub(super) fn children(
        &self,
        node: &Node,
        j: usize,
        bound: f64,
        dual: &Option<Arc<DualPoint>>,
        screened: &[usize],
        seq: &mut u64,
    ) -> (Option<Node>, Node) {
        let mut base = node.excluded.clone();
        for &i in screened {
            set_bit(&mut base, i);
        }
        let mut next = |fixed: Vec<usize>, excluded: Vec<u64>| {
            *seq += 1;
            Node {
                fixed,
                excluded,
                bound,
                dual: dual.clone(),
                depth: node.depth + 1,
                seq: *seq,
            }
        };
        let mut fixed = node.fixed.clone();
        let at = fixed.binary_search(&j).unwrap_or_else(|e| e);
        fixed.insert(at, j);
        let include = self.admissible(&fixed).then(|| {
            let mut excluded = base.clone();
            for &c in &self.member_of[j] {
                let g = &self.constraints[c];
                let taken = g
                    .sites
                    .iter()
                    .filter(|i| fixed.binary_search(i).is_ok())
                    .count();
                if taken >= g.max {
                    for &i in &g.sites {
                        if fixed.binary_search(&i).is_err() {
                            set_bit(&mut excluded, i);
                        }
                    }
                }
            }
            next(fixed, excluded)
        });
        let mut excluded = base;
        set_bit(&mut excluded, j);
        let exclude = next(node.fixed.clone(), excluded);
        (include, exclude)
    }
}
