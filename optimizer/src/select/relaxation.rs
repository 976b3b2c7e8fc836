//! The convex relaxation of the k-of-m selection as a clarabel conic program (the conic forms are
//! written out in the [parent module](super)'s documentation), for the whole problem and for a
//! branch-and-bound node.
//!
//! A node fixes some sites in (`z_i = 1`, their blocks summed into a constant `C`) and some out
//! (`z_i = 0`, dropped); only the free sites keep a variable, so the node's program is the root
//! program on fewer candidates with `C` added to the information matrix (in `b`) and `r = k − |in|`
//! on the cardinality row. clarabel 0.11 has no warm start of its interior-point iterates, so every
//! node is solved from clarabel's own initial point; the parent's dual point is reused instead by
//! the cheap bounds of [`super::bounds`].

use super::criterion::SelectionCriterion;
use super::problem::SelectionProblem;
use super::report::Relaxation;
use crate::error::OptimizerError;
use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
    SupportedConeT::{ExponentialConeT, NonnegativeConeT, PSDTriangleConeT, ZeroConeT},
};
use nalgebra::Matrix3;
use std::time::Instant;

/// A node of the relaxation: `fixed` chosen, `free` undecided (ascending), `r` more to choose.
pub(super) struct Subproblem<'a> {
    pub fixed: &'a [usize],
    pub free: &'a [usize],
    pub r: usize,
}

/// clarabel's answer to a [`Subproblem`], whatever its status.
pub(super) struct RawRelaxation {
    /// Weights of the free sites, clamped to [0, 1].
    pub z: Vec<f64>,
    /// Primal and dual objectives (maximisation sign).
    pub primal: f64,
    pub dual: f64,
    pub status: SolverStatus,
    pub iterations: u32,
    /// The dual matrix of the information block of each PSD cone: `Y_e` per epoch
    /// (E-optimal), or the `C + X` block of the 6×6 cone (D-optimal, a candidate `W`).
    pub psd_duals: Vec<Matrix3<f64>>,
    /// Multiplier of each side constraint's row (0 for a row that was not needed).
    pub row_duals: Vec<f64>,
}

/// clarabel's `max_step_fraction` of each attempt: its default (0.99), then shorter steps.
const MAX_STEP_FRACTIONS: [f64; 3] = [0.99, 0.9, 0.8];

/// svec row offset of entry (r, c), r ≤ c, and its weight (√2 off the diagonal).
fn svec(r: usize, c: usize) -> (usize, f64) {
    let w = if r == c {
        1.0
    } else {
        std::f64::consts::SQRT_2
    };
    (c * (c + 1) / 2 + r, w)
}

impl SelectionProblem {
    /// Solve the convex relaxation with clarabel.
    pub fn relax(&self) -> Result<Relaxation, OptimizerError> {
        let started = Instant::now();
        let all: Vec<usize> = (0..self.candidates()).collect();
        let raw = self.solve_subproblem(&Subproblem {
            fixed: &[],
            free: &all,
            r: self.k,
        })?;
        if !matches!(
            raw.status,
            SolverStatus::Solved | SolverStatus::AlmostSolved
        ) {
            return Err(OptimizerError::Unsolved {
                what: "the relaxation",
                status: raw.status,
            });
        }
        Ok(Relaxation {
            bound: raw.primal.max(raw.dual),
            z: raw.z,
            primal: raw.primal,
            dual: raw.dual,
            iterations: raw.iterations,
            status: raw.status,
            solve_time_s: started.elapsed().as_secs_f64(),
        })
    }

    /// Build and solve the relaxation of `sub` (needs `1 ≤ r < free.len()`). Errors only when
    /// clarabel rejects the data; an unsolved status is returned for the caller to judge.
    pub(super) fn solve_subproblem(
        &self,
        sub: &Subproblem<'_>,
    ) -> Result<RawRelaxation, OptimizerError> {
        let program = self.conic_program(sub);
        let solver = self.solve_program(&program)?;
        Ok(self.read_solution(&solver, &program, sub.free.len()))
    }

    /// The conic program of `sub`: the selection rows, the side constraints, then the cones of
    /// the criterion.
    fn conic_program(&self, sub: &Subproblem<'_>) -> ConicProgram {
        let m = sub.free.len();
        let mut program = ConicProgram::default();
        program.selection_rows(m, sub.r);
        self.side_constraint_rows(&mut program, sub);
        // One non-negative cone over the box rows and the side-constraint rows.
        let nonnegative = program.rows() - 1;
        program.cones.push(NonnegativeConeT(nonnegative));
        match self.criterion {
            SelectionCriterion::LogDet => self.log_det_cones(&mut program, sub),
            SelectionCriterion::MinEig => self.min_eig_cones(&mut program, sub),
        }
        program
    }

    /// Side constraints on the free sites: `Σ_{G ∩ free} z ≤ max − |G ∩ fixed|`
    /// (`s = rhs − Σ z`), one row for every constraint with a free member.
    fn side_constraint_rows(&self, program: &mut ConicProgram, sub: &Subproblem<'_>) {
        let m = sub.free.len();
        for (id, c) in self.constraints.iter().enumerate() {
            let members: Vec<usize> = (0..m)
                .filter(|&p| c.sites.binary_search(&sub.free[p]).is_ok())
                .collect();
            if members.is_empty() {
                continue;
            }
            let taken = sub
                .fixed
                .iter()
                .filter(|i| c.sites.binary_search(i).is_ok())
                .count();
            let row = program.rows();
            for p in members {
                program.a.push(row, p, 1.0);
            }
            program.b.push(c.max as f64 - taken as f64);
            program.constraint_rows.push((id, row));
        }
    }

    /// D-optimal: variables z (m), L lower-triangular (6: (0,0) (1,0) (1,1) (2,0) (2,1) (2,2)),
    /// u (3); maximise `Σ u_j` with `[[C + X, L], [Lᵀ, Diag(d)]] ⪰ 0` and `(u_j, 1, d_j) ∈ K_exp`.
    fn log_det_cones(&self, program: &mut ConicProgram, sub: &Subproblem<'_>) {
        let m = sub.free.len();
        let constant = sub
            .fixed
            .iter()
            .fold(Matrix3::zeros(), |acc, &i| acc + self.summed[i]);
        let l_index = |r: usize, c: usize| m + r * (r + 1) / 2 + c;
        let u_index = |j: usize| m + 6 + j;
        program.q = vec![0.0; m + 9];
        for j in 0..3 {
            program.q[u_index(j)] = -1.0;
        }
        // svec of M = [[C + X, L], [Lᵀ, Diag(d)]] (6×6, upper triangle by columns, off-diagonal
        // entries × √2); s = b − A x = svec(M), so A = −coefficients and b carries C.
        let row = program.rows();
        let (a, b) = (&mut program.a, &mut program.b);
        b.extend(std::iter::repeat_n(0.0, 21));
        for c in 0..6 {
            for r in 0..=c {
                let (off, w) = svec(r, c);
                let idx = row + off;
                if c < 3 {
                    b[idx] = w * constant[(r, c)];
                    for (p, &i) in sub.free.iter().enumerate() {
                        let v = self.summed[i][(r, c)];
                        if v != 0.0 {
                            a.push(idx, p, -w * v);
                        }
                    }
                } else if r < 3 {
                    // M[r][c] = L[r][c − 3], non-zero for r ≥ c − 3.
                    let j = c - 3;
                    if r >= j {
                        a.push(idx, l_index(r, j), -w);
                    }
                } else if r == c {
                    let j = c - 3;
                    a.push(idx, l_index(j, j), -1.0);
                }
            }
        }
        program.cones.push(PSDTriangleConeT(6));
        // The first six svec entries are the C + X block: its dual is the W of the bound.
        program.psd_rows.push(row);
        // (u_j, 1, d_j) ∈ K_exp.
        for j in 0..3 {
            let row = program.rows();
            program.a.push(row, u_index(j), -1.0);
            program.b.push(0.0);
            program.b.push(1.0);
            program.a.push(row + 2, l_index(j, j), -1.0);
            program.b.push(0.0);
            program.cones.push(ExponentialConeT());
        }
    }

    /// E-optimal: variables z (m), t; maximise t with `s = svec(C_e + Σ z A^e − t I) ⪰ 0` for
    /// every epoch e.
    fn min_eig_cones(&self, program: &mut ConicProgram, sub: &Subproblem<'_>) {
        let m = sub.free.len();
        let t_index = m;
        program.q = vec![0.0; m + 1];
        program.q[t_index] = -1.0;
        for e in 0..self.blocks[0].len() {
            let constant = sub
                .fixed
                .iter()
                .fold(Matrix3::zeros(), |acc, &i| acc + self.blocks[i][e]);
            let row = program.rows();
            for c in 0..3 {
                for r in 0..=c {
                    let (off, w) = svec(r, c);
                    let idx = row + off;
                    for (p, &i) in sub.free.iter().enumerate() {
                        let v = self.blocks[i][e][(r, c)];
                        if v != 0.0 {
                            program.a.push(idx, p, -w * v);
                        }
                    }
                    if r == c {
                        program.a.push(idx, t_index, 1.0);
                    }
                    // b is pushed in svec order (c outer, r inner), as the rows are.
                    program.b.push(w * constant[(r, c)]);
                }
            }
            program.cones.push(PSDTriangleConeT(3));
            program.psd_rows.push(row);
        }
    }

    /// clarabel's defaults first; on a numerical failure (e.g. `InsufficientProgress` on the
    /// 0.5° grid with k = 4, where the default full steps stall), shorter steps. Returns the
    /// last attempt, solved or not.
    fn solve_program(&self, program: &ConicProgram) -> Result<DefaultSolver<f64>, OptimizerError> {
        let n_var = program.q.len();
        let t = &program.a;
        let a_mat = CscMatrix::new_from_triplets(
            program.rows(),
            n_var,
            t.rows.clone(),
            t.cols.clone(),
            t.vals.clone(),
        );
        let p = CscMatrix::<f64>::zeros((n_var, n_var));
        let mut last = None;
        for step in MAX_STEP_FRACTIONS {
            let settings = DefaultSettings::<f64> {
                verbose: self.solver_verbose,
                max_iter: 200,
                max_step_fraction: step,
                ..DefaultSettings::default()
            };
            let mut solver =
                DefaultSolver::new(&p, &program.q, &a_mat, &program.b, &program.cones, settings)
                    .map_err(|source| OptimizerError::ClarabelSetup {
                        what: "the relaxation",
                        source,
                    })?;
            solver.solve();
            let solved = matches!(
                solver.solution.status,
                SolverStatus::Solved | SolverStatus::AlmostSolved
            );
            if solved {
                return Ok(solver);
            }
            last = Some(solver);
        }
        Ok(last.expect("MAX_STEP_FRACTIONS is not empty"))
    }

    /// The weights of the `m` free sites, the objectives and the duals of `program`'s PSD
    /// blocks and side-constraint rows from clarabel's answer.
    fn read_solution(
        &self,
        solver: &DefaultSolver<f64>,
        program: &ConicProgram,
        m: usize,
    ) -> RawRelaxation {
        let sol = &solver.solution;
        let smat = |r0: usize| {
            let mut y = Matrix3::zeros();
            for c in 0..3 {
                for r in 0..=c {
                    let (off, w) = svec(r, c);
                    y[(r, c)] = sol.z[r0 + off] / w;
                    y[(c, r)] = y[(r, c)];
                }
            }
            y
        };
        let mut row_duals = vec![0.0; self.constraints.len()];
        for &(id, r) in &program.constraint_rows {
            row_duals[id] = sol.z[r];
        }
        RawRelaxation {
            z: sol.x[..m].iter().map(|v| v.clamp(0.0, 1.0)).collect(),
            primal: -solver.info.cost_primal,
            dual: -solver.info.cost_dual,
            status: sol.status,
            iterations: solver.info.iterations,
            psd_duals: program.psd_rows.iter().map(|&r0| smat(r0)).collect(),
            row_duals,
        }
    }
}

/// A relaxation in clarabel's form: minimise `qᵀx` subject to `s = b − A x` in `cones` (rows in
/// cone order); the answer's objective is `−qᵀx`.
#[derive(Default)]
struct ConicProgram {
    a: Triplets,
    b: Vec<f64>,
    cones: Vec<SupportedConeT<f64>>,
    q: Vec<f64>,
    /// First row of each PSD cone's information block.
    psd_rows: Vec<usize>,
    /// `(constraint id, row)` of the side constraints that have a row.
    constraint_rows: Vec<(usize, usize)>,
}

impl ConicProgram {
    /// Rows so far.
    fn rows(&self) -> usize {
        self.b.len()
    }

    /// `Σ z = r` (a zero cone), then `z ≥ 0` (`s = z`) and `z ≤ 1` (`s = 1 − z`), the first
    /// rows of the non-negative cone.
    fn selection_rows(&mut self, m: usize, r: usize) {
        for i in 0..m {
            self.a.push(0, i, 1.0);
        }
        self.b.push(r as f64);
        self.cones.push(ZeroConeT(1));
        for i in 0..m {
            self.a.push(1 + i, i, -1.0);
            self.a.push(1 + m + i, i, 1.0);
        }
        self.b.extend(std::iter::repeat_n(0.0, m));
        self.b.extend(std::iter::repeat_n(1.0, m));
    }
}

/// Coordinate (triplet) entries of the constraint matrix, assembled by clarabel's
/// [`CscMatrix::new_from_triplets`] (sorted by column then row, repeated entries summed).
#[derive(Default)]
struct Triplets {
    rows: Vec<usize>,
    cols: Vec<usize>,
    vals: Vec<f64>,
}

impl Triplets {
    fn push(&mut self, r: usize, c: usize, v: f64) {
        self.rows.push(r);
        self.cols.push(c);
        self.vals.push(v);
    }
}
