//! Valid upper bounds on the value of every admissible completion of a branch-and-bound node,
//! from dual points of the relaxation (Lagrangian weak duality, Boyd & Vandenberghe, *Convex
//! Optimization*, §5.1–5.2).
//!
//! A node chooses `r` more sites from its free set `U` on top of the fixed set `F` (blocks summed
//! into `C`, or `C_e` per epoch). For any subset `T ⊆ U`, `|T| = r`:
//!
//! * **D-optimal.** Concavity of `ln det` (B&V §3.1.5) gives, for every `W ≻ 0`,
//!   `ln det X ≤ −ln det W − 3 + ⟨W, X⟩`. With `X = C + Σ_{i∈T} A_i`, scores `g_i = ⟨W, A_i⟩` and
//!   multipliers `μ_c ≥ 0` of the side constraints `Σ_{i∈G_c} z_i ≤ u_c` (`u_c` less the fixed
//!   members), `⟨W, X⟩ ≤ G := ⟨W, C⟩ + max_{z∈[0,1]^U, Σz=r} Σ_i z_i (g_i − Σ_{c∋i} μ_c) + Σ_c μ_c u_c`;
//!   the maximum is the sum of the `r` largest adjusted scores. Scaling `(W, μ)` by `α = 3/G`
//!   (the best scale) gives the bound `3 ln(G/3) − ln det W`. At the relaxation's optimum
//!   (`W = X*⁻¹`, clarabel's multipliers) it equals the relaxation's value; with `W = I`, `μ = 0`
//!   it is the AM–GM (trace) bound `3 ln(tr X_max / 3)`.
//! * **E-optimal.** For `Y_e ⪰ 0` with `Σ_e tr Y_e = 1`,
//!   `min_e λ_min(M_e) ≤ Σ_e tr(Y_e) λ_min(M_e) ≤ Σ_e ⟨Y_e, M_e⟩`, and the same linear maximisation
//!   over `T` with scores `h_i = Σ_e ⟨Y_e, A_i^e⟩` bounds the right-hand side. `Y` comes from
//!   clarabel's dual of the PSD cones (projected onto the PSD cone and normalised); the trace
//!   bound is `min_e (tr C_e + top_r tr A_i^e) / 3` (`Y = I/3` at one epoch).
//!
//! Every dual point gives a valid bound, however inaccurate the solver was: the node's own
//! solution makes it tight, the parent's makes it a cheap bound tried before the solver is called
//! (the dual counterpart of a warm start), and it certifies the answer even when clarabel stops
//! early (`AlmostSolved`, `InsufficientProgress`). The bounds are exact up to floating-point
//! rounding of a few 3×3 products (≲ 1e-13 here, far below the default gap tolerance 1e-6).

use super::criterion::SelectionCriterion;
use super::dual_point::{DualPoint, Scored, inner, top_sum};
use super::problem::SelectionProblem;
use super::relaxation::{RawRelaxation, Subproblem};
use nalgebra::Matrix3;

impl SelectionProblem {
    /// The dual point's base and adjusted scores on `sub`; `None` for a `W` that is not positive
    /// definite.
    fn scored(&self, dual: &DualPoint, sub: &Subproblem<'_>) -> Option<Scored> {
        let (mut base, mut scores, ln_det_w, mu) = match dual {
            DualPoint::LogDet { w, mu } => {
                let chol = w.cholesky()?;
                let ln_det_w = 2.0 * chol.l().diagonal().map(f64::ln).sum();
                let constant = sub
                    .fixed
                    .iter()
                    .fold(Matrix3::zeros(), |acc, &i| acc + self.summed[i]);
                let scores: Vec<f64> = sub
                    .free
                    .iter()
                    .map(|&i| inner(w, &self.summed[i]))
                    .collect();
                (inner(w, &constant), scores, Some(ln_det_w), mu)
            }
            DualPoint::MinEig { y, mu } => {
                let base = y
                    .iter()
                    .enumerate()
                    .map(|(e, ye)| {
                        let c = sub
                            .fixed
                            .iter()
                            .fold(Matrix3::zeros(), |acc, &i| acc + self.blocks[i][e]);
                        inner(ye, &c)
                    })
                    .sum();
                let scores = sub
                    .free
                    .iter()
                    .map(|&i| {
                        y.iter()
                            .zip(&self.blocks[i])
                            .map(|(ye, a)| inner(ye, a))
                            .sum()
                    })
                    .collect();
                (base, scores, None, mu)
            }
        };
        for (c, &m) in self.constraints.iter().zip(mu) {
            if m > 0.0 {
                let taken = sub
                    .fixed
                    .iter()
                    .filter(|i| c.sites.binary_search(i).is_ok())
                    .count();
                base += m * (c.max as f64 - taken as f64);
            }
        }
        if mu.iter().any(|&m| m > 0.0) {
            for (s, &i) in scores.iter_mut().zip(sub.free) {
                *s -= self.member_of[i]
                    .iter()
                    .map(|&c| mu[c].max(0.0))
                    .sum::<f64>();
            }
        }
        Some(Scored {
            base,
            scores,
            ln_det_w,
        })
    }

    /// The bound of the dual point `dual` on the node `sub` (module docs); +∞ when `dual` gives
    /// none.
    pub(super) fn dual_bound(&self, dual: &DualPoint, sub: &Subproblem<'_>) -> f64 {
        match self.scored(dual, sub) {
            Some(mut s) => {
                let top = top_sum(&mut s.scores, sub.r);
                s.finish(s.base + top)
            }
            None => f64::INFINITY,
        }
    }

    /// Reduced-cost screening (reduced-cost fixing of integer programming, Nemhauser & Wolsey,
    /// *Integer and Combinatorial Optimization*, 1988): the free sites whose inclusion alone
    /// bounds every completion at or below `threshold`, and the largest such bound. With site i
    /// forced in, the bound is `finish(base + s_i + Σ of the r − 1 largest other scores)`; the
    /// sites can be excluded from the whole subtree.
    pub(super) fn screen(
        &self,
        dual: &DualPoint,
        sub: &Subproblem<'_>,
        threshold: f64,
    ) -> (Vec<usize>, f64) {
        let Some(s) = self.scored(dual, sub) else {
            return (Vec::new(), f64::NEG_INFINITY);
        };
        if sub.r == 0 || s.scores.len() < sub.r {
            return (Vec::new(), f64::NEG_INFINITY);
        }
        let mut sorted = s.scores.clone();
        sorted.sort_unstable_by(|a, b| b.total_cmp(a));
        // Sites outside the r − 1 largest: forced in, the others' best r − 1 are the largest.
        let top_rm1: f64 = sorted[..sub.r - 1].iter().sum();
        let cutoff = sorted[sub.r - 1];
        let mut out = Vec::new();
        let mut worst = f64::NEG_INFINITY;
        for (p, &v) in s.scores.iter().enumerate() {
            if v >= cutoff {
                continue;
            }
            let b = s.finish(s.base + v + top_rm1);
            if b <= threshold {
                out.push(sub.free[p]);
                worst = worst.max(b);
            }
        }
        (out, worst)
    }

    /// The trace bound of the node: AM–GM `3 ln(tr/3)` (D-optimal) or the smallest per-epoch
    /// `tr/3` (E-optimal), on the largest traces among the free sites, side constraints ignored.
    pub(super) fn trace_bound(&self, sub: &Subproblem<'_>) -> f64 {
        match self.criterion {
            SelectionCriterion::LogDet => self.dual_bound(
                &DualPoint::LogDet {
                    w: Matrix3::identity(),
                    mu: Vec::new(),
                },
                sub,
            ),
            SelectionCriterion::MinEig => (0..self.blocks[0].len())
                .map(|e| {
                    let c: f64 = sub.fixed.iter().map(|&i| self.blocks[i][e].trace()).sum();
                    let mut scores: Vec<f64> = sub
                        .free
                        .iter()
                        .map(|&i| self.blocks[i][e].trace())
                        .collect();
                    (c + top_sum(&mut scores, sub.r)) / 3.0
                })
                .fold(f64::INFINITY, f64::min),
        }
    }

    /// The dual point of a node's relaxation solution, `None` when it gives none (a singular
    /// relaxed FIM, a zero PSD dual, non-finite output).
    pub(super) fn dual_from_relaxation(
        &self,
        sub: &Subproblem<'_>,
        raw: &RawRelaxation,
    ) -> Option<DualPoint> {
        if !raw.z.iter().chain(&raw.row_duals).all(|v| v.is_finite()) {
            return None;
        }
        let mu: Vec<f64> = raw.row_duals.iter().map(|m| m.max(0.0)).collect();
        match self.criterion {
            SelectionCriterion::LogDet => {
                let x = sub
                    .fixed
                    .iter()
                    .fold(Matrix3::zeros(), |acc, &i| acc + self.summed[i])
                    + sub
                        .free
                        .iter()
                        .zip(&raw.z)
                        .fold(Matrix3::zeros(), |acc, (&i, z)| acc + self.summed[i] * *z);
                // Two candidates for W: the inverse of the relaxed FIM (exact at the exact
                // optimum, but first-order sensitive to errors in z) and clarabel's dual of the
                // information block (as accurate as the dual objective). The tighter one wins.
                let inverse = x.cholesky().map(|c| c.inverse());
                let candidates = inverse.into_iter().chain(raw.psd_duals.first().copied());
                candidates
                    .map(|w| (w + w.transpose()) * 0.5)
                    .filter(|w| w.iter().all(|v| v.is_finite()) && w.cholesky().is_some())
                    .map(|w| DualPoint::LogDet { w, mu: mu.clone() })
                    .map(|d| (self.dual_bound(&d, sub), d))
                    .min_by(|a, b| a.0.total_cmp(&b.0))
                    .map(|(_, d)| d)
            }
            SelectionCriterion::MinEig => {
                if raw
                    .psd_duals
                    .iter()
                    .any(|y| !y.iter().all(|v| v.is_finite()))
                {
                    return None;
                }
                let y: Vec<Matrix3<f64>> = raw
                    .psd_duals
                    .iter()
                    .map(|y| {
                        let eig = y.symmetric_eigen();
                        let d = eig.eigenvalues.map(|l| l.max(0.0));
                        eig.eigenvectors * Matrix3::from_diagonal(&d) * eig.eigenvectors.transpose()
                    })
                    .collect();
                let total: f64 = y.iter().map(|m| m.trace()).sum();
                if !(total.is_finite() && total > 0.0) {
                    return None;
                }
                Some(DualPoint::MinEig {
                    y: y.iter().map(|m| m / total).collect(),
                    mu: mu.iter().map(|m| m / total).collect(),
                })
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::select::problem::{AtMost, LN_DET_FLOOR};
    use nalgebra::Vector3;

    /// Deterministic pseudo-random numbers in [−1, 1) (SplitMix64).
    struct Mix(u64);
    impl Mix {
        fn next(&mut self) -> f64 {
            self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
            let mut z = self.0;
            z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
            z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
            ((z ^ (z >> 31)) >> 11) as f64 / (1u64 << 52) as f64 - 1.0
        }
        fn psd(&mut self, rank: usize) -> Matrix3<f64> {
            (0..rank).fold(Matrix3::zeros(), |a, _| {
                let v = Vector3::new(self.next(), self.next(), self.next());
                a + v * v.transpose()
            })
        }
    }

    /// Best value over the admissible completions of `fixed` by `r` sites of `free`.
    fn best_completion(p: &SelectionProblem, fixed: &[usize], free: &[usize], r: usize) -> f64 {
        let mut best = f64::NEG_INFINITY;
        let n = free.len();
        for mask in 0u32..(1 << n) {
            if mask.count_ones() as usize != r {
                continue;
            }
            let mut s = fixed.to_vec();
            s.extend((0..n).filter(|b| mask >> b & 1 == 1).map(|b| free[b]));
            if p.admissible(&s) {
                best = best.max(p.value(&s));
            }
        }
        best
    }

    #[test]
    fn every_dual_point_bounds_every_completion_and_screening_is_safe() {
        let mut rng = Mix(42);
        let mut screened = 0;
        for trial in 0..40 {
            let criterion = if trial % 2 == 0 {
                SelectionCriterion::LogDet
            } else {
                SelectionCriterion::MinEig
            };
            let blocks: Vec<Vec<Matrix3<f64>>> = (0..9)
                .map(|_| (0..2).map(|_| rng.psd(1 + trial % 3)).collect())
                .collect();
            let cap = AtMost {
                sites: vec![1, 2, 3, 4],
                max: 1,
            };
            let p = SelectionProblem::new(blocks, 4, criterion)
                .unwrap()
                .with_constraints(if trial % 4 < 2 { vec![cap] } else { vec![] })
                .unwrap();
            let fixed = [0usize];
            let free: Vec<usize> = (2..9).collect();
            let sub = Subproblem {
                fixed: &fixed,
                free: &free,
                r: 3,
            };
            let best = best_completion(&p, &fixed, &free, 3);
            let mu = vec![rng.next().abs(); p.constraints().len()];
            let dual = match criterion {
                SelectionCriterion::LogDet => DualPoint::LogDet {
                    w: rng.psd(3) + Matrix3::identity() * 0.05,
                    mu,
                },
                SelectionCriterion::MinEig => {
                    let y = [rng.psd(1), rng.psd(2)];
                    let t: f64 = y.iter().map(|m| m.trace()).sum();
                    DualPoint::MinEig {
                        y: y.iter().map(|m| m / t).collect(),
                        mu: mu.iter().map(|m| m / t).collect(),
                    }
                }
            };
            let tol = 1e-9 * best.abs().max(1.0);
            for (name, b) in [
                ("dual", p.dual_bound(&dual, &sub)),
                ("trace", p.trace_bound(&sub)),
            ] {
                assert!(b + tol >= best, "trial {trial} {name}: {b} < {best}");
            }
            // The node's own relaxation: its dual point bounds the relaxed optimum itself (weak
            // duality holds for fractional z too) and is tight there.
            let raw = p.solve_subproblem(&sub).unwrap();
            let own = p.dual_from_relaxation(&sub, &raw).unwrap();
            let mut z = vec![0.0; 9];
            z[0] = 1.0;
            for (&i, w) in free.iter().zip(&raw.z) {
                z[i] = *w;
            }
            let relaxed = p.value_weighted(&z);
            let b = p.dual_bound(&own, &sub);
            assert!(
                b >= relaxed - 1e-7,
                "trial {trial}: own bound {b} < relaxed {relaxed}"
            );
            assert!(
                b <= relaxed + 1e-6,
                "trial {trial}: own bound {b} ≫ relaxed {relaxed}"
            );
            assert!(b + tol >= best);
            // Screening removes no site of a completion above the threshold (thresholds just
            // below the best completion, so the sites of the best one must stay).
            let scale = best.abs().max(0.1);
            for (d, threshold) in [
                (&dual, best - 0.05 * scale),
                (&own, best - 1e-3 * scale),
                (&own, best - 0.05 * scale),
            ] {
                let (out, worst) = p.screen(d, &sub, threshold);
                assert!(worst <= threshold);
                screened += out.len();
                for &i in &out {
                    let rest: Vec<usize> = free.iter().copied().filter(|&j| j != i).collect();
                    let with_i = best_completion(&p, &[0, i], &rest, 2);
                    assert!(with_i <= threshold + tol, "trial {trial}: screened {i}");
                }
            }
        }
        assert!(screened > 0, "the screening check never ran");
    }

    #[test]
    fn the_value_floor_is_ln_1e_300() {
        assert_eq!(LN_DET_FLOOR, 1e-300f64.ln());
    }
}
