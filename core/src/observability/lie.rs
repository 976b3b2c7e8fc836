//! Exact Lie derivatives and the nonlinear observability matrix (seed 002 eq. 9–12, seed 000
//! eq. 11–13) by Taylor-mode forward AD.
//!
//! For an autonomous system, the k-th Lie derivative is the k-th time derivative of the output
//! along the flow φ_t of f:
//!
//! ```text
//! L_f^k h(x0) = dᵏ/dtᵏ h(φ_t(x0)) |_{t=0}
//! ```
//!
//! (induction on seed 002 eq. 9: d/dt L^k h(φ_t) = ∇L^k h · f = L^{k+1} h). So instead of nesting
//! n − 1 gradient operators (whose cost grows exponentially with the order — the paper's
//! "> 10,000 s"), we compute the Taylor series of the trajectory x(t) = φ_t(x0) to degree n − 1
//! in [`Jet`] arithmetic by Picard iteration, `x_{k+1} = [f(x(t))]_k / (k + 1)` (each pass fixes
//! one more coefficient; n − 1 passes), and evaluate h on it: the k-th coefficient times k! is
//! `L_f^k h(x0)`. The coefficients are `DualSVec64<N>` numbers seeded with the unit vectors, so the
//! same pass also yields the exact gradients `∇L_f^k h(x0)` — the rows of O (eq. 12). Everything
//! is exact to rounding: no symbolic algebra, no finite differences.

use super::jet::Jet;
use super::system::ObservedSystem;
use nalgebra::{Const, DMatrix, SVector, U1};
use num_dual::DualSVec64;
use rand_distr::num_traits::Zero;

/// Lie derivatives `L_f^k h_j(x0)`, k = 0..n−1, and their gradients.
#[derive(Debug, Clone, PartialEq)]
pub struct LieDerivatives {
    /// `values[(k, j)] = L_f^k h_j(x0)` (n × m).
    pub values: DMatrix<f64>,
    /// The observability matrix O (eq. 12): row `k·m + j` is `∇L_f^k h_j(x0)` ((n·m) × n).
    pub matrix: DMatrix<f64>,
}

type Coef<const N: usize> = DualSVec64<N>;

/// Taylor coefficients (degree < N) of the trajectory through `x0`, with gradients w.r.t. `x0`.
fn flow_jet<S: ObservedSystem<N>, const N: usize>(
    sys: &S,
    x0: &SVector<f64, N>,
) -> SVector<Jet<Coef<N>, N>, N> {
    let mut x: SVector<Jet<Coef<N>, N>, N> =
        SVector::from_fn(|i, _| Jet::constant(Coef::<N>::from_re(x0[i]).derivative(i)));
    // After pass p the coefficients of degree ≤ p + 1 are exact.
    for pass in 0..N.saturating_sub(1) {
        let fx = sys.f(&x);
        for i in 0..N {
            for k in 0..=pass {
                x[i].c[k + 1] = fx[i].c[k] / ((k + 1) as f64);
            }
        }
    }
    x
}

/// The exact Lie derivatives of every output up to order n − 1 at `x0`, with their gradients.
pub fn lie_derivatives<S: ObservedSystem<N>, const N: usize>(
    sys: &S,
    x0: &SVector<f64, N>,
) -> LieDerivatives {
    let m = sys.outputs();
    let x = flow_jet(sys, x0);
    let mut y = vec![Jet::<Coef<N>, N>::zero(); m];
    sys.h(&x, &mut y);
    let mut values = DMatrix::zeros(N, m);
    let mut matrix = DMatrix::zeros(N * m, N);
    let mut fact = 1.0;
    for k in 0..N {
        if k > 0 {
            fact *= k as f64;
        }
        for (j, yj) in y.iter().enumerate() {
            let c = yj.c[k];
            values[(k, j)] = c.re * fact;
            let g = c.eps.unwrap_generic(Const::<N>, U1);
            for i in 0..N {
                matrix[(k * m + j, i)] = g[i] * fact;
            }
        }
    }
    LieDerivatives { values, matrix }
}

/// The nonlinear observability matrix O_Σ (seed 002 eq. 12) at `x0`, exact.
pub fn lie_matrix<S: ObservedSystem<N>, const N: usize>(
    sys: &S,
    x0: &SVector<f64, N>,
) -> DMatrix<f64> {
    lie_derivatives(sys, x0).matrix
}
