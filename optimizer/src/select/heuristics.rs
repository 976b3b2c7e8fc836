//! Heuristic k-subsets and the exact answer by enumeration: top-k rounding of the relaxed
//! weights, the swap local search, the greedy selection, brute force, and
//! [`SelectionProblem::solve`] which certifies the better heuristic with the relaxation bound
//! (Joshi & Boyd 2009, §IV: rounding and local optimisation of the relaxed solution).
//!
//! Every heuristic keeps to the problem's side constraints ([`AtMost`](super::AtMost)); with constraints a
//! heuristic may find no admissible k-subset, which is reported as `None`.

use super::criterion::SelectionCriterion;
use super::problem::SelectionProblem;
use super::problem::ln_det;
use super::report::Selection;
use super::report::SelectionReport;
use crate::error::OptimizerError;
use nalgebra::Matrix3;
use std::time::Instant;

impl SelectionProblem {
    /// The `k` candidates with the largest weights (ties to the lower index), skipping a
    /// candidate that would break a side constraint; `None` when fewer than `k` fit.
    pub fn round(&self, z: &[f64]) -> Option<Selection> {
        let order: Vec<usize> = (0..self.candidates()).collect();
        self.round_among(&[], &order, self.k, z)
    }

    /// Top-`r` rounding of the weights `z` (one per entry of `pool`) added to `fixed`.
    pub(super) fn round_among(
        &self,
        fixed: &[usize],
        pool: &[usize],
        r: usize,
        z: &[f64],
    ) -> Option<Selection> {
        let mut order: Vec<usize> = (0..pool.len()).collect();
        order.sort_by(|&i, &j| z[j].total_cmp(&z[i]).then(pool[i].cmp(&pool[j])));
        let mut chosen = fixed.to_vec();
        for p in order {
            if chosen.len() == fixed.len() + r {
                break;
            }
            chosen.push(pool[p]);
            if !self.admissible(&chosen) {
                chosen.pop();
            }
        }
        (chosen.len() == fixed.len() + r).then(|| self.selection(chosen))
    }

    /// Swap local search from `start`: repeatedly apply the best exchange of a chosen and an
    /// unchosen candidate while it improves the value by more than 1e-12 (relative). Returns the
    /// local optimum and the number of evaluations.
    pub fn swap_improve(&self, start: &Selection) -> (Selection, usize) {
        let pool: Vec<usize> = (0..self.candidates()).collect();
        self.swap_search(&[], &start.indices, &pool)
    }

    /// Swap local search that keeps `fixed` and exchanges members of `movable` with candidates
    /// of `pool` (the swap of [`SelectionProblem::swap_improve`] restricted to a branch-and-bound
    /// node). Only admissible exchanges are tried.
    pub(super) fn swap_search(
        &self,
        fixed: &[usize],
        movable: &[usize],
        pool: &[usize],
    ) -> (Selection, usize) {
        let nf = fixed.len();
        let mut moving = movable.to_vec();
        moving.sort_unstable();
        let mut idx: Vec<usize> = fixed.iter().chain(&moving).copied().collect();
        let mut current = self.selection(idx.clone());
        let mut evals = 0;
        for _ in 0..10_000 {
            let mut best: Option<(usize, usize, f64)> = None;
            for pos in nf..idx.len() {
                for &cand in pool {
                    if idx.contains(&cand) {
                        continue;
                    }
                    let mut trial = idx.clone();
                    trial[pos] = cand;
                    if !self.admissible(&trial) {
                        continue;
                    }
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
                    // The next round scans the chosen sites in ascending order.
                    moving[pos - nf] = cand;
                    moving.sort_unstable();
                    idx = fixed.iter().chain(&moving).copied().collect();
                    current = self.selection(idx.clone());
                }
                _ => break,
            }
        }
        (current, evals)
    }

    /// Greedy selection: add the candidate that increases the value most, k times (admissible
    /// candidates only); `None` when the side constraints stop it before k.
    pub fn greedy(&self) -> (Option<Selection>, usize) {
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
                if !self.admissible(&trial) {
                    continue;
                }
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
            match best {
                Some((c, _)) => chosen.push(c),
                None => return (None, evals),
            }
        }
        (Some(self.selection(chosen)), evals)
    }

    /// The best admissible k-subset by enumeration (lexicographic order, ties to the first), when
    /// there are at most `limit` subsets; `None` above the limit or when no k-subset is
    /// admissible.
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
        let mut best = self.admissible(&idx).then(|| self.selection(idx.clone()));
        loop {
            // Next combination in lexicographic order.
            let mut i = k;
            while i > 0 && idx[i - 1] == m - k + i - 1 {
                i -= 1;
            }
            if i == 0 {
                return best;
            }
            idx[i - 1] += 1;
            for j in i..k {
                idx[j] = idx[j - 1] + 1;
            }
            if !self.admissible(&idx) {
                continue;
            }
            let v = self.value(&idx);
            if best.as_ref().is_none_or(|b| v > b.value) {
                best = Some(Selection {
                    indices: idx.clone(),
                    value: v,
                });
            }
        }
    }

    /// Relaxation, rounding, swap improvement and greedy. Errors when the solver fails or
    /// neither rounding nor greedy finds an admissible k-subset.
    pub fn solve(&self) -> Result<SelectionReport, OptimizerError> {
        let started = Instant::now();
        let relaxation = self.relax()?;
        let rounded = self.round(&relaxation.z);
        let (from_rounded, e1) = match &rounded {
            Some(s) => {
                let (s, e) = self.swap_improve(s);
                (Some(s), e)
            }
            None => (None, 0),
        };
        let (greedy, e2) = self.greedy();
        let (from_greedy, e3) = match &greedy {
            Some(s) => {
                let (s, e) = self.swap_improve(s);
                (Some(s), e)
            }
            None => (None, 0),
        };
        let improved = match (from_rounded, from_greedy) {
            (Some(r), Some(g)) => {
                if g.value > r.value {
                    g
                } else {
                    r
                }
            }
            (Some(s), None) | (None, Some(s)) => s,
            (None, None) => {
                return Err(OptimizerError::Infeasible(format!(
                    "neither rounding nor greedy found {} sites that satisfy the side constraints",
                    self.k
                )));
            }
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
