//! Choose k of m candidate sites: the convex relaxation of Joshi & Boyd ("Sensor selection via
//! convex optimization", IEEE TSP 57(2), 2009), solved by clarabel, with rounding, a swap local
//! search and certified gaps.
//!
//! **Data.** Each candidate i has one or more 3×3 positive semidefinite information blocks
//! `A_i^e` (e = epochs). For the D-optimal criterion the blocks are summed into one matrix per
//! candidate; for the E-optimal one every epoch counts separately.
//!
//! **Problems** (Boolean `z_i ∈ {0, 1}`, `Σ z_i = k`, relaxed to `0 ≤ z_i ≤ 1`):
//!
//! * [`SelectionCriterion::LogDet`] — `max log det Σ_i z_i A_i`. Conic form: with a lower
//!   triangular `L` (diagonal d) and `u ∈ R³`,
//!   `[[Σ z_i A_i, L], [Lᵀ, Diag(d)]] ⪰ 0` (one 6×6 PSD cone) and `(u_j, 1, d_j) ∈ K_exp`
//!   (`e^{u_j} ≤ d_j`, three exponential cones); maximise `Σ u_j`. The PSD condition is
//!   `Σ z A ⪰ L Diag(d)⁻¹ Lᵀ`, whose determinant is `Π d_j`, and the Cholesky factor makes it tight,
//!   so the optimum is `log det Σ z A`.
//! * [`SelectionCriterion::MinEig`] — `max t` subject to `Σ_i z_i A_i^e − t I ⪰ 0` for every
//!   epoch e (one 3×3 PSD cone each): the E-optimal, max-min λ_min design as an SDP.
//!
//! The relaxation's optimum is an **upper bound** on every k-subset's value. The bound reported is
//! the larger of the solver's primal and dual objectives (the dual objective is the certificate),
//! so `gap = bound − value(S)` bounds how far any selection S is from the best k-subset.
//!
//! **Rounding.** The k largest `z_i`, then a swap local search (exchange a chosen and an unchosen
//! site while the value improves). The greedy selection, also swap-improved, is a second start;
//! the better local optimum is the answer.

use crate::OptimizerError;
use crate::ground::{GroundProblem, Site};
use entrynav::beacons::ground_visibility_margin;
use entrynav::math::{norm, sub};
use nalgebra::Matrix3;
use nalgebra::Vector3;
use std::time::Instant;

mod relaxation;

/// The design criterion.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum SelectionCriterion {
    /// D-optimal: `log det Σ_{i∈S} A_i` (blocks summed).
    LogDet,
    /// E-optimal: `min_e λ_min(Σ_{i∈S} A_i^e)`.
    MinEig,
}

impl SelectionCriterion {
    /// Name used on the command line and in reports: `logdet` or `min-eig`.
    pub fn name(self) -> &'static str {
        match self {
            SelectionCriterion::LogDet => "logdet",
            SelectionCriterion::MinEig => "min-eig",
        }
    }
}

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
    /// Solver status, e.g. `Solved`.
    pub status: String,
    /// Wall time of the solve \[s\].
    pub solve_time_s: f64,
}

/// Everything [`SelectionProblem::solve`] produces.
#[derive(Debug, Clone, PartialEq)]
pub struct SelectionReport {
    /// The relaxation and its bound.
    pub relaxation: Relaxation,
    /// The k largest relaxed weights.
    pub rounded: Selection,
    /// The better of the swap local searches started from `rounded` and from `greedy`: the
    /// answer.
    pub improved: Selection,
    /// The greedy heuristic.
    pub greedy: Selection,
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

/// Choose `k` of the candidates.
#[derive(Debug, Clone, PartialEq)]
pub struct SelectionProblem {
    blocks: Vec<Vec<Matrix3<f64>>>,
    summed: Vec<Matrix3<f64>>,
    k: usize,
    criterion: SelectionCriterion,
    solver_verbose: bool,
}

/// `ln det` of a 3×3 symmetric PSD matrix, floored at `ln 1e-300` (finite).
fn ln_det(m: &Matrix3<f64>) -> f64 {
    m.determinant().max(1e-300).ln()
}

fn min_eig(m: &Matrix3<f64>) -> f64 {
    m.symmetric_eigenvalues().min()
}

impl SelectionProblem {
    /// Candidates with information blocks `blocks[i][e]` (every candidate the same number ≥ 1 of
    /// symmetric PSD blocks), choose `k`.
    ///
    /// Errors: no candidates, `k == 0`, `k > m` (infeasible), ragged or non-finite blocks.
    pub fn new(
        blocks: Vec<Vec<Matrix3<f64>>>,
        k: usize,
        criterion: SelectionCriterion,
    ) -> Result<SelectionProblem, OptimizerError> {
        let m = blocks.len();
        if m == 0 {
            return Err(OptimizerError::Infeasible(
                "there are no candidate sites to choose from".into(),
            ));
        }
        if k == 0 {
            return Err(OptimizerError::InvalidInput("k must be at least 1".into()));
        }
        if k > m {
            return Err(OptimizerError::Infeasible(format!(
                "k = {k} sites requested but only {m} candidate site(s) exist"
            )));
        }
        let e = blocks[0].len();
        if e == 0 || blocks.iter().any(|b| b.len() != e) {
            return Err(OptimizerError::InvalidInput(
                "every candidate needs the same, non-zero number of information blocks".into(),
            ));
        }
        if blocks
            .iter()
            .flatten()
            .flat_map(|b| b.iter())
            .any(|v| !v.is_finite())
        {
            return Err(OptimizerError::InvalidInput(
                "information blocks must be finite".into(),
            ));
        }
        let summed = blocks
            .iter()
            .map(|b| b.iter().fold(Matrix3::zeros(), |a, m| a + m))
            .collect();
        Ok(SelectionProblem {
            blocks,
            summed,
            k,
            criterion,
            solver_verbose: false,
        })
    }

    /// The same problem with clarabel's iteration log printed to stdout (`on`) or not (the
    /// default).
    pub fn with_solver_verbose(mut self, on: bool) -> SelectionProblem {
        self.solver_verbose = on;
        self
    }

    /// Number of candidates m.
    pub fn candidates(&self) -> usize {
        self.blocks.len()
    }

    /// Number to choose k.
    pub fn k(&self) -> usize {
        self.k
    }

    /// The criterion.
    pub fn criterion(&self) -> SelectionCriterion {
        self.criterion
    }

    /// Criterion value of the (possibly fractional) weights `z` (one per candidate).
    pub fn value_weighted(&self, z: &[f64]) -> f64 {
        match self.criterion {
            SelectionCriterion::LogDet => ln_det(
                &self
                    .summed
                    .iter()
                    .zip(z)
                    .fold(Matrix3::zeros(), |a, (m, w)| a + m * *w),
            ),
            SelectionCriterion::MinEig => (0..self.blocks[0].len())
                .map(|e| {
                    min_eig(
                        &self
                            .blocks
                            .iter()
                            .zip(z)
                            .fold(Matrix3::zeros(), |a, (b, w)| a + b[e] * *w),
                    )
                })
                .fold(f64::INFINITY, f64::min),
        }
    }

    /// Criterion value of the subset `indices`.
    pub fn value(&self, indices: &[usize]) -> f64 {
        match self.criterion {
            SelectionCriterion::LogDet => ln_det(
                &indices
                    .iter()
                    .fold(Matrix3::zeros(), |a, &i| a + self.summed[i]),
            ),
            SelectionCriterion::MinEig => (0..self.blocks[0].len())
                .map(|e| {
                    min_eig(
                        &indices
                            .iter()
                            .fold(Matrix3::zeros(), |a, &i| a + self.blocks[i][e]),
                    )
                })
                .fold(f64::INFINITY, f64::min),
        }
    }

    fn selection(&self, mut indices: Vec<usize>) -> Selection {
        indices.sort_unstable();
        let value = self.value(&indices);
        Selection { indices, value }
    }

    /// The `k` candidates with the largest weights (ties to the lower index).
    pub fn round(&self, z: &[f64]) -> Selection {
        let mut order: Vec<usize> = (0..self.candidates()).collect();
        order.sort_by(|&i, &j| z[j].total_cmp(&z[i]).then(i.cmp(&j)));
        order.truncate(self.k);
        self.selection(order)
    }

    /// Swap local search from `start`: repeatedly apply the best exchange of a chosen and an
    /// unchosen candidate while it improves the value by more than 1e-12 (relative). Returns the
    /// local optimum and the number of evaluations.
    pub fn swap_improve(&self, start: &Selection) -> (Selection, usize) {
        let m = self.candidates();
        let mut current = start.clone();
        let mut evals = 0;
        for _ in 0..10_000 {
            let mut best: Option<(usize, usize, f64)> = None;
            for pos in 0..current.indices.len() {
                for cand in 0..m {
                    if current.indices.contains(&cand) {
                        continue;
                    }
                    let mut trial = current.indices.clone();
                    trial[pos] = cand;
                    let v = self.value(&trial);
                    evals += 1;
                    if best.is_none_or(|b| v > b.2) {
                        best = Some((pos, cand, v));
                    }
                }
            }
            match best {
                Some((pos, cand, v))
                    if v > current.value + 1e-12 * current.value.abs().max(1.0) =>
                {
                    let mut idx = current.indices.clone();
                    idx[pos] = cand;
                    current = self.selection(idx);
                }
                _ => break,
            }
        }
        (current, evals)
    }

    /// Greedy selection: add the candidate that increases the value most, k times.
    pub fn greedy(&self) -> (Selection, usize) {
        let mut chosen: Vec<usize> = Vec::with_capacity(self.k);
        let mut evals = 0;
        for _ in 0..self.k {
            let mut best: Option<(usize, f64)> = None;
            for c in 0..self.candidates() {
                if chosen.contains(&c) {
                    continue;
                }
                let mut trial = chosen.clone();
                trial.push(c);
                // With fewer than three sites log det may be −∞-like; rank by the regularised
                // value so the first picks are still informative.
                let v = if trial.len() < 3 && self.criterion == SelectionCriterion::LogDet {
                    let m = trial
                        .iter()
                        .fold(Matrix3::zeros(), |a, &i| a + self.summed[i]);
                    ln_det(&(m + Matrix3::identity() * 1e-6))
                } else {
                    self.value(&trial)
                };
                evals += 1;
                if best.is_none_or(|b| v > b.1) {
                    best = Some((c, v));
                }
            }
            if let Some((c, _)) = best {
                chosen.push(c);
            }
        }
        (self.selection(chosen), evals)
    }

    /// The best k-subset by enumeration, when there are at most `limit` subsets.
    pub fn brute_force(&self, limit: usize) -> Option<Selection> {
        let m = self.candidates();
        let k = self.k;
        let mut count: f64 = 1.0;
        for j in 0..k {
            count *= (m - j) as f64 / (j + 1) as f64;
        }
        if count > limit as f64 {
            return None;
        }
        let mut idx: Vec<usize> = (0..k).collect();
        let mut best = self.selection(idx.clone());
        loop {
            // Next combination in lexicographic order.
            let mut i = k;
            while i > 0 && idx[i - 1] == m - k + i - 1 {
                i -= 1;
            }
            if i == 0 {
                return Some(best);
            }
            idx[i - 1] += 1;
            for j in i..k {
                idx[j] = idx[j - 1] + 1;
            }
            let v = self.value(&idx);
            if v > best.value {
                best = Selection {
                    indices: idx.clone(),
                    value: v,
                };
            }
        }
    }

    /// Relaxation, rounding, swap improvement and greedy.
    pub fn solve(&self) -> Result<SelectionReport, OptimizerError> {
        let started = Instant::now();
        let relaxation = self.relax()?;
        let rounded = self.round(&relaxation.z);
        let (from_rounded, e1) = self.swap_improve(&rounded);
        let (greedy, e2) = self.greedy();
        let (from_greedy, e3) = self.swap_improve(&greedy);
        let improved = if from_greedy.value > from_rounded.value {
            from_greedy
        } else {
            from_rounded
        };
        Ok(SelectionReport {
            relaxation,
            evaluations: e1 + e2 + e3 + 1,
            rounded,
            improved,
            greedy,
            elapsed_s: started.elapsed().as_secs_f64(),
        })
    }
}

/// Information blocks of candidate `sites` on `ground`'s trajectory (planet-fixed frame, unit σ):
///
/// * `epoch_step_s = None` — one block per site, the time-averaged FIM
///   `A_i = (1/T) Σ_k w_k n_i(t_k) n_i(t_k)ᵀ` (trace ≤ 1, so `ln det Σ_{i∈S} A_i ≤ 3 ln(k/3)`);
/// * `Some(s)` — the instantaneous `n_i(t) n_i(t)ᵀ` at samples about `s` seconds apart (first and
///   last sample included), for the max-min-over-time E-optimal design.
///
/// Samples where a site does not see the vehicle (eq. 52) contribute nothing.
pub fn site_information(
    ground: &GroundProblem,
    sites: &[Site],
    epoch_step_s: Option<f64>,
) -> Result<Vec<Vec<Matrix3<f64>>>, OptimizerError> {
    let tr = ground.trajectory();
    let fixed = ground.fixed_positions();
    let radius = tr.planet.radius;
    let outer = |b: &[f64; 3], k: usize| -> Matrix3<f64> {
        let v = fixed[k];
        if ground_visibility_margin(b, &v) <= 0.0 {
            return Matrix3::zeros();
        }
        let d = sub(&v, b);
        let u = Vector3::from(d) / norm(&d);
        u * u.transpose()
    };
    let epochs: Option<Vec<usize>> = match epoch_step_s {
        None => None,
        Some(s) => {
            if !(s.is_finite() && s > 0.0) {
                return Err(OptimizerError::InvalidInput(format!(
                    "epoch spacing {s} s must be positive"
                )));
            }
            let mut ks = Vec::new();
            let mut next = tr.times[0];
            for (k, t) in tr.times.iter().enumerate() {
                if *t >= next - 1e-9 {
                    ks.push(k);
                    next = t + s;
                }
            }
            if ks.last() != Some(&(tr.len() - 1)) {
                ks.push(tr.len() - 1);
            }
            Some(ks)
        }
    };
    let duration = tr.duration();
    Ok(sites
        .iter()
        .map(|site| {
            let b = site.fixed_position(radius);
            match &epochs {
                None => vec![(0..tr.len()).fold(Matrix3::zeros(), |acc, k| {
                    acc + outer(&b, k) * (tr.weights[k] / duration)
                })],
                Some(ks) => ks.iter().map(|&k| outer(&b, k)).collect(),
            }
        })
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn diag(a: f64, b: f64, c: f64) -> Matrix3<f64> {
        Matrix3::from_diagonal(&nalgebra::Vector3::new(a, b, c))
    }

    #[test]
    fn relaxation_of_axis_aligned_sensors_is_exact() {
        // Three axis sensors and a weak isotropic one: choose 3 → the axes, log det = 0.
        let blocks = vec![
            vec![diag(1.0, 0.0, 0.0)],
            vec![diag(0.0, 1.0, 0.0)],
            vec![diag(0.0, 0.0, 1.0)],
            vec![diag(0.2, 0.2, 0.2)],
        ];
        let p = SelectionProblem::new(blocks.clone(), 3, SelectionCriterion::LogDet).unwrap();
        let r = p.solve().unwrap();
        assert!(r.relaxation.bound >= -1e-6, "{r:?}");
        assert!(r.relaxation.bound < 0.05, "{r:?}");
        assert_eq!(r.improved.indices, vec![0, 1, 2]);
        let e = SelectionProblem::new(blocks, 3, SelectionCriterion::MinEig).unwrap();
        let r = e.solve().unwrap();
        assert!((r.relaxation.bound - 1.0).abs() < 0.2, "{r:?}");
        assert!((r.improved.value - 1.0).abs() < 1e-12);
    }
}
