//! The joint moments of several filters' deviations from the nominal, stacked as
//! X = \[δx̂_1; …; δx̂_M\] (M blocks of N), with the truth's parameters θ (Cov θ = I): E\[XXᵀ\],
//! E\[Xθᵀ\] and E\[X\]. Every step of the fusion's LinCov is a linear map of X,
//!
//! ```text
//! X ← A X + G (Z θ + v) + b,   v ~ N(0, diag R_t),
//! ```
//!
//! so E\[Xθᵀ\] ← A E\[Xθᵀ\] + G Z, E\[XXᵀ\] ← A E\[XXᵀ\] Aᵀ + A E\[Xθᵀ\] Zᵀ Gᵀ + G Z E\[θXᵀ\] Aᵀ +
//! G (Z Zᵀ + R_t) Gᵀ and E\[X\] ← A E\[X\] + b (Maybeck vol. 1 eq. 6-10 to 6-12 with a constant
//! truth; the blocks' cross-moments are the local filters' correlations through their common
//! start, their shared channels and θ, which covariance intersection does not know).

use nalgebra::{DMatrix, DVector, SMatrix, SVector};

/// E\[XXᵀ\], E\[Xθᵀ\], E\[X\] of M stacked N-vectors.
#[derive(Debug, Clone)]
pub(super) struct Joint {
    /// E\[XXᵀ\] (MN × MN).
    xx: DMatrix<f64>,
    /// E\[Xθᵀ\] (MN × p).
    xt: DMatrix<f64>,
    /// E\[X\].
    m: DVector<f64>,
}

/// The block-diagonal MN × MN matrix with the blocks `blocks`.
pub(super) fn block_diagonal<const N: usize>(blocks: &[SMatrix<f64, N, N>]) -> DMatrix<f64> {
    let mut out = DMatrix::zeros(N * blocks.len(), N * blocks.len());
    for (i, b) in blocks.iter().enumerate() {
        out.view_mut((i * N, i * N), (N, N)).copy_from(b);
    }
    out
}

/// The MN-vector stacking `blocks`.
pub(super) fn stack<const N: usize>(blocks: &[SVector<f64, N>]) -> DVector<f64> {
    DVector::from_iterator(
        N * blocks.len(),
        blocks.iter().flat_map(|b| b.iter().copied()),
    )
}

impl Joint {
    /// Every one of `members` blocks equal to the deviation with moments (`c`, `chh`, `m`): the
    /// filters start from one estimate.
    pub(super) fn replicated<const N: usize>(
        c: &[SVector<f64, N>],
        chh: &SMatrix<f64, N, N>,
        m: &SVector<f64, N>,
        members: usize,
    ) -> Self {
        let size = N * members;
        Joint {
            xx: DMatrix::from_fn(size, size, |i, j| chh[(i % N, j % N)]),
            xt: DMatrix::from_fn(size, c.len(), |i, j| c[j][i % N]),
            m: DVector::from_fn(size, |i, _| m[i % N]),
        }
    }

    /// E\[δx̂_i θᵀ\] ζ for block `i`: the covariance of that filter's deviation with a measurement
    /// whose sensitivity to θ is `zeta`.
    pub(super) fn cross<const N: usize>(&self, i: usize, zeta: &DVector<f64>) -> SVector<f64, N> {
        let v = self.xt.rows(i * N, N) * zeta;
        SVector::from_fn(|r, _| v[r])
    }

    /// E\[δx̂_i δx̂_iᵀ\] of block `i` (covariance plus mean outer product).
    pub(super) fn block_second_moment<const N: usize>(&self, i: usize) -> SMatrix<f64, N, N> {
        SMatrix::from_fn(|r, c| {
            self.xx[(i * N + r, i * N + c)] + self.m[i * N + r] * self.m[i * N + c]
        })
    }

    /// E\[δx̂_i\] += b.
    pub(super) fn add_mean<const N: usize>(&mut self, i: usize, b: &SVector<f64, N>) {
        for r in 0..N {
            self.m[i * N + r] += b[r];
        }
    }

    /// Time update of every block with the same transition and drift: δx̂_i ← Φ δx̂_i + d.
    pub(super) fn propagate<const N: usize>(
        &mut self,
        phi: &SMatrix<f64, N, N>,
        drift: &SVector<f64, N>,
    ) {
        let members = self.m.len() / N;
        let none = (
            DMatrix::zeros(N * members, 0),
            DMatrix::zeros(0, self.xt.ncols()),
        );
        let a = block_diagonal(&vec![*phi; members]);
        self.apply(&a, &none.0, &none.1, &[], &stack(&vec![*drift; members]));
    }

    /// X ← A X + G (Z θ + v) + b with v's variances `r_t` (`g` is MN × m, `z` m × p).
    pub(super) fn apply(
        &mut self,
        a: &DMatrix<f64>,
        g: &DMatrix<f64>,
        z: &DMatrix<f64>,
        r_t: &[f64],
        b: &DVector<f64>,
    ) {
        let gz = g * z;
        let axt = a * &self.xt;
        let mut zz = z * z.transpose();
        for (i, r) in r_t.iter().enumerate() {
            zz[(i, i)] += r;
        }
        let cross = &axt * gz.transpose();
        let xx = a * &self.xx * a.transpose() + &cross + cross.transpose() + g * zz * g.transpose();
        self.xx = (&xx + xx.transpose()) * 0.5;
        self.xt = axt + gz;
        self.m = a * &self.m + b;
    }

    /// X ← F X (a deterministic linear map of the stacked deviations, e.g. the feedback of a
    /// fused estimate to every filter).
    pub(super) fn map(&mut self, f: &DMatrix<f64>) {
        let xx = f * &self.xx * f.transpose();
        self.xx = (&xx + xx.transpose()) * 0.5;
        self.xt = f * &self.xt;
        self.m = f * &self.m;
    }

    /// The moments of the combination W X (`w` is N × MN): the rows c_j = E\[θ_j WX\], E\[WX XᵀWᵀ\]
    /// and E\[WX\], as the single-filter recursion keeps them.
    pub(super) fn combined<const N: usize>(
        &self,
        w: &DMatrix<f64>,
    ) -> (Vec<SVector<f64, N>>, SMatrix<f64, N, N>, SVector<f64, N>) {
        let c = w * &self.xt;
        let xx = w * &self.xx * w.transpose();
        let m = w * &self.m;
        (
            (0..c.ncols())
                .map(|j| SVector::from_fn(|i, _| c[(i, j)]))
                .collect(),
            SMatrix::from_fn(|i, j| 0.5 * (xx[(i, j)] + xx[(j, i)])),
            SVector::from_fn(|i, _| m[i]),
        )
    }
}
