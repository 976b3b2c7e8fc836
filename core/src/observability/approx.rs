//! The two approximate observability matrices of seed 002 §3.1: the quadratic approximation of the
//! Lie derivatives (eq. 13–17) and the linearisation (eq. 18–19).
//!
//! Both need only first and second derivatives at x0, computed exactly by forward AD: the Jacobian
//! J_f of f (`DualSVec64`), and the gradient and Hessian of every output (`Dual2SVec64`, one pass of
//! h for all outputs).
//!
//! **Quadratic recursion.** With `L^k h_j ≈ L^k h_j0 + J^k d + ½ dᵀ H^k d` (d = x − x0, eq. 13) and
//! `f ≈ f0 + J_f d` (eq. 14), `L^{k+1} h_j = ∇L^k h_j · f` (eq. 15) gives
//!
//! ```text
//! J^{k+1} = J^k J_f + ½ ((H^k + H^kᵀ) f0)ᵀ        (eq. 16, as printed)
//! H^{k+1} = (H^k + H^kᵀ) J_f                       (eq. 16 prints ½ (H^k + H^kᵀ) J_f)
//! ```
//!
//! The printed Hessian update carries a factor ½ that belongs to eq. 15's last line, which writes
//! the quadratic term *without* eq. 13's ½; re-used in eq. 13's form at the next order it would halve
//! the curvature at every step. We keep eq. 13's convention throughout, so that the recursion is
//! exact whenever f is affine and h quadratic (checked in the tests against the exact method).

use super::system::ObservedSystem;
use nalgebra::{Const, DMatrix, SMatrix, SVector, U1};
use num_dual::{Dual2SVec64, DualSVec64, jacobian};
use rand_distr::num_traits::Zero;

/// `f(x0)` and `J_f(x0)`.
fn f_jacobian<S: ObservedSystem<N>, const N: usize>(
    sys: &S,
    x0: &SVector<f64, N>,
) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
    jacobian(|x| sys.f(&x), x0)
}

/// Jacobian of h at x0 (m × N).
pub fn output_jacobian<S: ObservedSystem<N>, const N: usize>(
    sys: &S,
    x0: &SVector<f64, N>,
) -> DMatrix<f64> {
    let m = sys.outputs();
    let x: SVector<DualSVec64<N>, N> =
        SVector::from_fn(|i, _| DualSVec64::<N>::from_re(x0[i]).derivative(i));
    let mut y = vec![DualSVec64::<N>::zero(); m];
    sys.h(&x, &mut y);
    let mut jh = DMatrix::zeros(m, N);
    for (j, yj) in y.iter().enumerate() {
        let g = yj.eps.unwrap_generic(Const::<N>, U1);
        for i in 0..N {
            jh[(j, i)] = g[i];
        }
    }
    jh
}

/// Gradient (1 × N) and Hessian (N × N) of every output at x0.
#[allow(clippy::type_complexity)]
fn output_hessians<S: ObservedSystem<N>, const N: usize>(
    sys: &S,
    x0: &SVector<f64, N>,
) -> Vec<(SMatrix<f64, 1, N>, SMatrix<f64, N, N>)> {
    let m = sys.outputs();
    let x: SVector<Dual2SVec64<N>, N> =
        SVector::from_fn(|i, _| Dual2SVec64::<N>::from_re(x0[i]).derivative(i));
    let mut y = vec![Dual2SVec64::<N>::zero(); m];
    sys.h(&x, &mut y);
    y.into_iter()
        .map(|yj| {
            (
                yj.v1.unwrap_generic(U1, Const::<N>),
                yj.v2.unwrap_generic(Const::<N>, Const::<N>),
            )
        })
        .collect()
}

/// Observability matrix by the quadratic approximation (seed 002 eq. 17): row `k·m + j` is
/// `J^k_{L_j}` from the recursion in the module documentation, k = 0..n−1.
pub fn quadratic_matrix<S: ObservedSystem<N>, const N: usize>(
    sys: &S,
    x0: &SVector<f64, N>,
) -> DMatrix<f64> {
    let m = sys.outputs();
    let (f0, jf) = f_jacobian(sys, x0);
    let mut o = DMatrix::zeros(N * m, N);
    for (j, (j0, h0)) in output_hessians(sys, x0).into_iter().enumerate() {
        let (mut jk, mut hk) = (j0, h0);
        for k in 0..N {
            for i in 0..N {
                o[(k * m + j, i)] = jk[i];
            }
            if k + 1 < N {
                let s = hk + hk.transpose();
                jk = jk * jf + (s * f0).transpose() * 0.5;
                hk = s * jf;
            }
        }
    }
    o
}

/// Observability matrix of the linearised system (seed 002 eq. 19): `[J_h; J_h J_f; …;
/// J_h J_f^{n−1}]`.
pub fn linear_matrix<S: ObservedSystem<N>, const N: usize>(
    sys: &S,
    x0: &SVector<f64, N>,
) -> DMatrix<f64> {
    let m = sys.outputs();
    let (_, jf) = f_jacobian(sys, x0);
    let jf = DMatrix::from_fn(N, N, |r, c| jf[(r, c)]);
    let mut block = output_jacobian(sys, x0);
    let mut o = DMatrix::zeros(N * m, N);
    for k in 0..N {
        o.view_mut((k * m, 0), (m, N)).copy_from(&block);
        if k + 1 < N {
            block = &block * &jf;
        }
    }
    o
}
