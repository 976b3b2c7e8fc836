//! What a selection gives: the chosen sites and their value ([`Selection`]), the relaxation's
//! bound ([`Relaxation`]) and both with the certified gap ([`SelectionReport`]).

use clarabel::solver::SolverStatus;

/// A k-subset of the candidates and its value.
#[derive(Debug, Clone, PartialEq)]
pub struct Selection {
    /// Candidate indices, ascending.
    pub indices: Vec<usize>,
    /// Criterion value.
    pub value: f64,
}

/// The solution of the convex relaxation.
#[derive(Debug, Clone, PartialEq)]
pub struct Relaxation {
    /// Relaxed weights `z ∈ [0, 1]^m`, `Σ z = k`.
    pub z: Vec<f64>,
    /// Upper bound on the value of every k-subset.
    pub bound: f64,
    /// The solver's primal objective (maximisation sign).
    pub primal: f64,
    /// The solver's dual objective (maximisation sign).
    pub dual: f64,
    /// Interior-point iterations.
    pub iterations: u32,
    /// clarabel's status: `Solved` or `AlmostSolved` (any other is an error of
    /// [`SelectionProblem::relax`](super::SelectionProblem::relax)); its `Display` is the variant name.
    pub status: SolverStatus,
    /// Wall time of the solve \[s\].
    pub solve_time_s: f64,
}

/// Everything [`SelectionProblem::solve`](super::SelectionProblem::solve) produces.
#[derive(Debug, Clone, PartialEq)]
pub struct SelectionReport {
    /// The relaxation and its bound.
    pub relaxation: Relaxation,
    /// The k largest relaxed weights (`None` when the side constraints stop the rounding).
    pub rounded: Option<Selection>,
    /// The better of the swap local searches started from `rounded` and from `greedy`: the
    /// answer.
    pub improved: Selection,
    /// The greedy heuristic (`None` when the side constraints stop it).
    pub greedy: Option<Selection>,
    /// Criterion evaluations made by rounding, swaps and greedy.
    pub evaluations: usize,
    /// Wall time of everything \[s\].
    pub elapsed_s: f64,
}

impl SelectionReport {
    /// `bound − value` of a selection: how far it can be from the best k-subset at most.
    pub fn gap(&self, s: &Selection) -> f64 {
        (self.relaxation.bound - s.value).max(0.0)
    }
}
