//! [`SelectionProblem`]: k of m candidate sites, their information blocks and side constraints
//! ([`AtMost`]), and the value of a selection.

use super::criterion::SelectionCriterion;
use super::report::Selection;
use crate::error::OptimizerError;
use nalgebra::Matrix3;

/// A side constraint: at most `max` of the candidates `sites` are chosen (the linear constraint
/// `Σ_{i∈sites} z_i ≤ max` of the relaxation).
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct AtMost {
    /// Candidate indices.
    pub sites: Vec<usize>,
    /// How many of them may be chosen.
    pub max: usize,
}

/// Choose `k` of the candidates.
#[derive(Debug, Clone, PartialEq)]
pub struct SelectionProblem {
    pub(super) blocks: Vec<Vec<Matrix3<f64>>>,
    pub(super) summed: Vec<Matrix3<f64>>,
    pub(super) k: usize,
    pub(super) criterion: SelectionCriterion,
    pub(super) solver_verbose: bool,
    pub(super) constraints: Vec<AtMost>,
    /// For each candidate, the constraints it belongs to.
    pub(super) member_of: Vec<Vec<usize>>,
}

/// The floor of [`SelectionProblem::value`] for the D-optimal criterion: `ln 1e-300`.
pub const LN_DET_FLOOR: f64 = -690.7755278982137;

/// `ln det` of a 3×3 symmetric PSD matrix, floored at `ln 1e-300` (finite).
pub(super) fn ln_det(m: &Matrix3<f64>) -> f64 {
    m.determinant().max(1e-300).ln()
}

pub(super) fn min_eig(m: &Matrix3<f64>) -> f64 {
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
            constraints: Vec::new(),
            member_of: vec![Vec::new(); m],
        })
    }

    /// The same problem with side constraints (replacing any earlier ones). Sites are sorted and
    /// deduplicated; constraints that cannot bind (`max ≥` their size) are dropped. Errors: a
    /// site index out of range.
    pub fn with_constraints(
        mut self,
        constraints: Vec<AtMost>,
    ) -> Result<SelectionProblem, OptimizerError> {
        let m = self.candidates();
        self.constraints.clear();
        self.member_of = vec![Vec::new(); m];
        for mut c in constraints {
            if let Some(bad) = c.sites.iter().find(|&&i| i >= m) {
                return Err(OptimizerError::InvalidInput(format!(
                    "side constraint names candidate {bad}, but there are only {m}"
                )));
            }
            c.sites.sort_unstable();
            c.sites.dedup();
            if c.max >= c.sites.len() {
                continue;
            }
            let id = self.constraints.len();
            for &i in &c.sites {
                self.member_of[i].push(id);
            }
            self.constraints.push(c);
        }
        Ok(self)
    }

    /// The side constraints that can bind.
    pub fn constraints(&self) -> &[AtMost] {
        &self.constraints
    }

    /// Whether the (partial) selection `indices` keeps every side constraint.
    pub fn admissible(&self, indices: &[usize]) -> bool {
        if self.constraints.is_empty() {
            return true;
        }
        let mut hits: Vec<usize> = indices
            .iter()
            .flat_map(|&i| self.member_of[i].iter().copied())
            .collect();
        hits.sort_unstable();
        hits.chunk_by(|a, b| a == b)
            .all(|run| run.len() <= self.constraints[run[0]].max)
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

    /// The selection of `indices` (sorted) with its value.
    pub(crate) fn selection(&self, mut indices: Vec<usize>) -> Selection {
        indices.sort_unstable();
        let value = self.value(&indices);
        Selection { indices, value }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::select::criterion::SelectionCriterion;
    use clarabel::solver::SolverStatus;
    use nalgebra::Matrix3;

    fn diag(a: f64, b: f64, c: f64) -> Matrix3<f64> {
        Matrix3::from_diagonal(&nalgebra::Vector3::new(a, b, c))
    }

    /// Three axis sensors and a weak isotropic one, choose 3. Both relaxations are exact here:
    /// they are concave and symmetric in the three axes, so an optimum has `z₁ = z₂ = z₃ = a`,
    /// `z₄ = 3 − 3a`, where `ln det = 3 ln(0.6 + 0.4a)` and `λmin = 0.6 + 0.4a` are largest at
    /// `a = 1`: the Boolean `z = (1, 1, 1, 0)`, whose values are `ln det I = 0` and `λmin(I) = 1`.
    /// clarabel's `Solved` status guarantees its duality gap within
    /// `tol_gap_abs + tol_gap_rel·|objective|`, so the bound must be that close to the optimum.
    #[test]
    fn relaxation_of_axis_aligned_sensors_is_exact() {
        let blocks = vec![
            vec![diag(1.0, 0.0, 0.0)],
            vec![diag(0.0, 1.0, 0.0)],
            vec![diag(0.0, 0.0, 1.0)],
            vec![diag(0.2, 0.2, 0.2)],
        ];
        let settings = clarabel::solver::DefaultSettings::<f64>::default();
        for (criterion, optimum) in [
            (SelectionCriterion::LogDet, 0.0),
            (SelectionCriterion::MinEig, 1.0),
        ] {
            let p = SelectionProblem::new(blocks.clone(), 3, criterion).unwrap();
            let r = p.solve().unwrap();
            let x = &r.relaxation;
            let tol = settings.tol_gap_abs + settings.tol_gap_rel * f64::max(optimum, 1.0);
            assert_eq!(x.status, SolverStatus::Solved, "{criterion:?}: {x:?}");
            assert!(
                (x.bound - optimum).abs() <= tol,
                "{criterion:?}: bound {} vs the exact optimum {optimum} (tolerance {tol:e})",
                x.bound
            );
            assert!(x.primal <= x.bound && x.bound - x.primal <= tol, "{x:?}");
            for (zi, want) in x.z.iter().zip([1.0, 1.0, 1.0, 0.0]) {
                assert!((zi - want).abs() < 1e-6, "{criterion:?}: z = {:?}", x.z);
            }
            assert_eq!(r.improved.indices, vec![0, 1, 2]);
            assert_eq!(r.improved.value, optimum);
        }
    }
}
