//! The convex relaxation of the k-of-m selection as a clarabel conic program (the conic forms are
//! written out in the [parent module](super)'s documentation).

use super::*;
use clarabel::algebra::CscMatrix;
use clarabel::solver::{
    DefaultSettings, DefaultSolver, IPSolver, SolverStatus, SupportedConeT,
    SupportedConeT::{ExponentialConeT, NonnegativeConeT, PSDTriangleConeT, ZeroConeT},
};

impl SelectionProblem {
    /// Solve the convex relaxation with clarabel.
    pub fn relax(&self) -> Result<Relaxation, OptimizerError> {
        let started = Instant::now();
        let m = self.candidates();
        let mut a = Triplets::default();
        let mut b = Vec::new();
        let mut cones: Vec<SupportedConeT<f64>> = Vec::new();
        // Σ z = k.
        for i in 0..m {
            a.push(0, i, 1.0);
        }
        b.push(self.k as f64);
        cones.push(ZeroConeT(1));
        // z ≥ 0 (s = z) and z ≤ 1 (s = 1 − z).
        for i in 0..m {
            a.push(1 + i, i, -1.0);
            a.push(1 + m + i, i, 1.0);
        }
        b.extend(std::iter::repeat_n(0.0, m));
        b.extend(std::iter::repeat_n(1.0, m));
        cones.push(NonnegativeConeT(2 * m));
        let mut row = 1 + 2 * m;
        let n_var;
        let mut q;
        match self.criterion {
            SelectionCriterion::LogDet => {
                // Variables: z (m), L lower-triangular (6: (0,0) (1,0) (1,1) (2,0) (2,1) (2,2)),
                // u (3).
                let l_index = |r: usize, c: usize| m + r * (r + 1) / 2 + c;
                let u_index = |j: usize| m + 6 + j;
                n_var = m + 9;
                q = vec![0.0; n_var];
                for j in 0..3 {
                    q[u_index(j)] = -1.0;
                }
                // svec of M = [[X, L], [Lᵀ, Diag(d)]] (6×6, upper triangle by columns, off-diagonal
                // entries × √2); s = b − A x = svec(M), so A = −coefficients, b = 0.
                let r2 = std::f64::consts::SQRT_2;
                for c in 0..6 {
                    for r in 0..=c {
                        let idx = row + c * (c + 1) / 2 + r;
                        let w = if r == c { 1.0 } else { r2 };
                        if c < 3 {
                            for (i, s) in self.summed.iter().enumerate() {
                                let v = s[(r, c)];
                                if v != 0.0 {
                                    a.push(idx, i, -w * v);
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
                b.extend(std::iter::repeat_n(0.0, 21));
                cones.push(PSDTriangleConeT(6));
                row += 21;
                // (u_j, 1, d_j) ∈ K_exp.
                for j in 0..3 {
                    a.push(row, u_index(j), -1.0);
                    b.push(0.0);
                    b.push(1.0);
                    a.push(row + 2, l_index(j, j), -1.0);
                    b.push(0.0);
                    cones.push(ExponentialConeT());
                    row += 3;
                }
            }
            SelectionCriterion::MinEig => {
                // Variables: z (m), t. s = svec(Σ z A^e − t I) for every epoch.
                let t_index = m;
                n_var = m + 1;
                q = vec![0.0; n_var];
                q[t_index] = -1.0;
                let r2 = std::f64::consts::SQRT_2;
                for e in 0..self.blocks[0].len() {
                    for c in 0..3 {
                        for r in 0..=c {
                            let idx = row + c * (c + 1) / 2 + r;
                            let w = if r == c { 1.0 } else { r2 };
                            for (i, blk) in self.blocks.iter().enumerate() {
                                let v = blk[e][(r, c)];
                                if v != 0.0 {
                                    a.push(idx, i, -w * v);
                                }
                            }
                            if r == c {
                                a.push(idx, t_index, 1.0);
                            }
                        }
                    }
                    b.extend(std::iter::repeat_n(0.0, 6));
                    cones.push(PSDTriangleConeT(3));
                    row += 6;
                }
            }
        }
        let a_mat = a.into_csc(row, n_var);
        let p = CscMatrix::<f64>::zeros((n_var, n_var));
        let settings = DefaultSettings::<f64> {
            verbose: self.solver_verbose,
            max_iter: 200,
            ..DefaultSettings::default()
        };
        let mut solver = DefaultSolver::new(&p, &q, &a_mat, &b, &cones, settings)
            .map_err(|e| OptimizerError::Solver(format!("clarabel setup: {e:?}")))?;
        solver.solve();
        let status = solver.solution.status;
        if !matches!(status, SolverStatus::Solved | SolverStatus::AlmostSolved) {
            return Err(OptimizerError::Solver(format!(
                "clarabel did not solve the relaxation: {status:?}"
            )));
        }
        let z: Vec<f64> = solver.solution.x[..m]
            .iter()
            .map(|v| v.clamp(0.0, 1.0))
            .collect();
        let primal = -solver.info.cost_primal;
        let dual = -solver.info.cost_dual;
        Ok(Relaxation {
            bound: primal.max(dual),
            z,
            primal,
            dual,
            iterations: solver.info.iterations,
            status: format!("{status:?}"),
            solve_time_s: started.elapsed().as_secs_f64(),
        })
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

    /// The `m × n` compressed sparse column matrix of the entries.
    fn into_csc(self, m: usize, n: usize) -> CscMatrix<f64> {
        CscMatrix::new_from_triplets(m, n, self.rows, self.cols, self.vals)
    }
}
