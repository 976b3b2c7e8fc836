//! The optimal-CI-weight objective on the scaled information matrices, with its gradient and
//! Hessian in ω ([`Problem`]), and the factorisation of `Y(ω)` it is evaluated at ([`Factor`]);
//! the search over the simplex is [`super::ci_weights`].

use super::ci_scaling::Mat;
use super::spd::{cholesky, inverse_from_cholesky, lower_inverse};
use nalgebra::{Cholesky, Const, DMatrix};

/// Objective (and optionally gradient and Hessian in ω) of the optimal-weight problem on the
/// scaled information matrices. With `Y = Σ ω_i Y_i`, `M_i = Y⁻¹ Y_i`, `S_i = M_i Y⁻¹`:
/// * det: `f = −log det Y`, `∂f/∂ω_i = −tr(Y⁻¹Y_i) = −tr M_i`, `∂²f/∂ω_i∂ω_j = tr(M_i M_j)`;
/// * trace: `f = tr Y⁻¹`, `∂f/∂ω_i = −tr(Y⁻¹Y_iY⁻¹) = −tr S_i`,
///   `∂²f/∂ω_i∂ω_j = 2 tr(Y⁻¹Y_iY⁻¹Y_jY⁻¹) = 2 tr(M_i S_j)`.
///
/// The det derivatives are formed on the symmetric `B_i = T Y_i Tᵀ`, `T = L⁻¹` for the Cholesky
/// factor `Y = L Lᵀ` (so `Y⁻¹ = TᵀT`): `tr M_i = tr B_i` and `tr(M_i M_j) = ⟨B_i, B_j⟩_F`. With
/// `T` triangular and only `B_i`'s lower triangle formed, that is ≈ N³ (1/6 + 4/6 n) multiply–adds
/// and half-size Frobenius products, against N³ (1/3 + n) for `Y⁻¹` and the products `Y⁻¹Y_i`.
///
/// `m`, `s` (trace) and `b` (det, lower triangles by columns) are work space; `g`, `h` receive
/// the gradient and Hessian.
pub(super) struct Problem<'a, const N: usize> {
    pub(super) ys: &'a [Mat<N>],
    pub(super) trace: bool,
    pub(super) m: Vec<Mat<N>>,
    pub(super) s: Vec<Mat<N>>,
    pub(super) b: Vec<[[f64; N]; N]>,
    pub(super) g: Vec<f64>,
    pub(super) h: DMatrix<f64>,
}

/// Factorisation of `Y(ω)`: Cholesky factor, objective value and (trace objective) `Y⁻¹`.
pub(super) struct Factor<const N: usize> {
    pub(super) chol: Cholesky<f64, Const<N>>,
    pub(super) f: f64,
    pub(super) yinv: Option<Mat<N>>,
}

impl<'a, const N: usize> Problem<'a, N> {
    pub(super) fn new(ys: &'a [Mat<N>], trace: bool) -> Self {
        let (n, z) = (ys.len(), Mat::<N>::zeros());
        let (g, h) = (vec![0.0; n], DMatrix::zeros(n, n));
        let (mats, lowers) = if trace { (n, 0) } else { (0, n) };
        Problem {
            ys,
            trace,
            m: vec![z; mats],
            s: vec![z; mats],
            b: vec![[[0.0; N]; N]; lowers],
            g,
            h,
        }
    }

    /// Factor `Y(ω)` and evaluate `f`; `None` if not positive definite.
    pub(super) fn factor(&self, w: &[f64]) -> Option<Factor<N>> {
        // Σ ω_i Y_i accumulated in place, entry by entry: the same sums as adding the scaled
        // matrices, without the temporaries.
        let mut y = Mat::<N>::zeros();
        for (yi, wi) in self.ys.iter().zip(w) {
            for (acc, v) in y.as_mut_slice().iter_mut().zip(yi.as_slice()) {
                *acc += v * *wi;
            }
        }
        let chol = cholesky(&y)?;
        let yinv = self.trace.then(|| inverse_from_cholesky(chol.l_dirty()));
        let f = match &yinv {
            Some(yi) => yi.trace(),
            None => -2.0 * chol.l_dirty().diagonal().map(f64::ln).sum(),
        };
        f.is_finite().then_some(Factor { chol, f, yinv })
    }

    /// Gradient `g` and Hessian `h` at a factorisation.
    pub(super) fn derivatives(&mut self, fac: &Factor<N>) {
        match &fac.yinv {
            Some(yinv) => self.trace_derivatives(yinv),
            None => self.det_derivatives(fac),
        }
    }

    /// The det objective's gradient alone, `g_i = −tr(Y⁻¹Y_i) = −⟨Y⁻¹, Y_i⟩_F` from `Y⁻¹`
    /// (≈ N³/3 + n N² multiply–adds against ≈ N³ (1/6 + 4/6 n) for the Hessian too); `h` keeps
    /// the last Hessian (a chord step, see [`optimal_weights`]). `false` for the trace
    /// objective, which has no cheaper gradient.
    pub(super) fn det_gradient(&mut self, fac: &Factor<N>) -> bool {
        if fac.yinv.is_some() {
            return false;
        }
        let yinv = inverse_from_cholesky(fac.chol.l_dirty());
        for (g, yi) in self.g.iter_mut().zip(self.ys) {
            *g = -yinv.dot(yi);
        }
        true
    }

    /// The trace objective's derivatives from `Y⁻¹`.
    pub(super) fn trace_derivatives(&mut self, yinv: &Mat<N>) {
        let (m, s) = (&mut self.m, &mut self.s);
        for i in 0..self.ys.len() {
            m[i] = yinv * self.ys[i];
            s[i] = m[i] * yinv;
            self.g[i] = -s[i].trace();
            let mt = m[i].transpose();
            for (j, sj) in s[..=i].iter().enumerate() {
                // 2 tr(M_i S_j) = 2 Σ (M_iᵀ)_kl (S_j)_kl.
                let hij = 2.0 * mt.dot(sj);
                (self.h[(i, j)], self.h[(j, i)]) = (hij, hij);
            }
        }
    }

    /// The det objective's derivatives from `B_i = T Y_i Tᵀ` (see [`Problem`]).
    #[allow(clippy::needless_range_loop)] // columns of several arrays at one index
    pub(super) fn det_derivatives(&mut self, fac: &Factor<N>) {
        // t[k][r] = T_rk, zero for r < k.
        let t = lower_inverse(fac.chol.l_dirty());
        for i in 0..self.ys.len() {
            // y[c][k] = (Y_i)_kc.
            let y = &self.ys[i].data.0;
            // C = T Y_i by columns: C[:, c] = Σ_k T[:, k] (Y_i)_kc, T[:, k] non-zero from row k.
            let mut cm = [[0.0f64; N]; N];
            for c in 0..N {
                for k in 0..N {
                    let v = y[c][k];
                    for r in k..N {
                        cm[c][r] += t[k][r] * v;
                    }
                }
            }
            // B = C Tᵀ, lower triangle: B[r, s] = Σ_{k ≤ s} C[r, k] T_sk for r ≥ s.
            let b = &mut self.b[i];
            let mut trace = 0.0;
            for s in 0..N {
                b[s] = [0.0; N];
                for k in 0..=s {
                    let v = t[k][s];
                    for r in s..N {
                        b[s][r] += cm[k][r] * v;
                    }
                }
                trace += b[s][s];
            }
            self.g[i] = -trace;
            for j in 0..=i {
                // ⟨B_i, B_j⟩_F from the lower triangles: diagonal once, the rest twice.
                let (bi, bj) = (&self.b[i], &self.b[j]);
                let (mut diag, mut off) = (0.0, 0.0);
                for s in 0..N {
                    diag += bi[s][s] * bj[s][s];
                    for r in s + 1..N {
                        off += bi[s][r] * bj[s][r];
                    }
                }
                let hij = diag + 2.0 * off;
                (self.h[(i, j)], self.h[(j, i)]) = (hij, hij);
            }
        }
    }
}
