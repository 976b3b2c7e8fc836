//! Scalar abstraction and small fixed-size vector helpers shared by every model.
//!
//! Models are written once, generic over [`Real`], and evaluated either in `f64` or in
//! forward-mode dual numbers from `num-dual` (e.g. `DualSVec64<N>`), which gives exact
//! Jacobians without symbolic algebra.

use nalgebra::Const;
use nalgebra::{SMatrix, SVector};
use num_dual::{Derivative, DualNum, DualVec, jacobian};

/// A real scalar the models can be evaluated in: `f64` or a (static-size) dual number.
pub trait Real: DualNum<Primitive = f64> + Copy + nalgebra::Scalar {}
impl<T: DualNum<Primitive = f64> + Copy + nalgebra::Scalar> Real for T {}

/// A 3-vector of scalars, used for positions, velocities and accelerations.
pub type V3<T> = [T; 3];

/// Whether every value is finite (no NaN, no ±∞), without an early exit: the test the filters
/// run on every state and covariance each step, as one vectorisable pass over the storage
/// (`m.as_slice()`) instead of nalgebra's strided element iterator.
pub fn all_finite(values: &[f64]) -> bool {
    values.iter().fold(true, |ok, v| ok & v.is_finite())
}

/// Dot product of two 3-vectors.
#[inline]
pub fn dot<T: Real>(a: &V3<T>, b: &V3<T>) -> T {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// Cross product `a × b`.
#[inline]
pub fn cross<T: Real>(a: &V3<T>, b: &V3<T>) -> V3<T> {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// Euclidean norm.
#[inline]
pub fn norm<T: Real>(a: &V3<T>) -> T {
    dot(a, a).sqrt()
}

/// `a - b`.
#[inline]
pub fn sub<T: Real>(a: &V3<T>, b: &V3<T>) -> V3<T> {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `a + b`.
#[inline]
pub fn add<T: Real>(a: &V3<T>, b: &V3<T>) -> V3<T> {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `s · a`.
#[inline]
pub fn scale<T: Real>(s: T, a: &V3<T>) -> V3<T> {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// Lift an `f64` 3-vector into any [`Real`] type (as constants).
#[inline]
pub fn lift3<T: Real>(a: &V3<f64>) -> V3<T> {
    [T::from(a[0]), T::from(a[1]), T::from(a[2])]
}

/// Jacobian `∂g/∂x` of a vector function by forward-mode AD, with the value `g(x)`.
///
/// `g` must be written generically so that it can be called with `DualVec<f64, N>` scalars.
pub fn ad_jacobian<const M: usize, const N: usize>(
    g: impl FnOnce(
        SVector<DualVec<f64, nalgebra::Const<N>>, N>,
    ) -> SVector<DualVec<f64, nalgebra::Const<N>>, M>,
    x: &SVector<f64, N>,
) -> (SVector<f64, M>, SMatrix<f64, M, N>) {
    jacobian(g, x)
}

/// Forward-mode dual number carrying a gradient with respect to `N` seeded variables.
pub type Dual<const N: usize> = DualVec<f64, Const<N>>;

/// Seed `x` as `N` independent AD variables: component i carries the unit gradient e_i.
pub fn seed_duals<const N: usize>(x: &SVector<f64, N>) -> SVector<Dual<N>, N> {
    SVector::from_fn(|i, _| {
        DualVec::new(
            x[i],
            Derivative::derivative_generic(Const::<N>, Const::<1>, i),
        )
    })
}

/// A dual number seeded on `K` variables as one on `N ≥ K` variables of which they are the
/// first `K` (the gradient is padded with zeros).
pub fn lift_dual<const K: usize, const N: usize>(d: &Dual<K>) -> Dual<N> {
    let g = dual_gradient(d);
    let padded = SVector::<f64, N>::from_fn(|i, _| if i < K { g[i] } else { 0.0 });
    DualVec::new(d.re, Derivative::some(padded))
}

/// Gradient (∂/∂x of the seeded variables) carried by a dual number.
pub fn dual_gradient<const N: usize>(d: &Dual<N>) -> SVector<f64, N> {
    d.eps.unwrap_generic(Const::<N>, Const::<1>)
}

/// Central finite-difference Jacobian with per-component steps `h_i = rel·max(|x_i|, floor_i)`.
///
/// Used only to *check* AD and analytic derivatives in tests and diagnostics.
pub fn fd_jacobian<const M: usize, const N: usize>(
    g: impl Fn(&SVector<f64, N>) -> SVector<f64, M>,
    x: &SVector<f64, N>,
    steps: &SVector<f64, N>,
) -> SMatrix<f64, M, N> {
    let mut jac = SMatrix::<f64, M, N>::zeros();
    for j in 0..N {
        let mut xp = *x;
        let mut xm = *x;
        xp[j] += steps[j];
        xm[j] -= steps[j];
        let d = (g(&xp) - g(&xm)) / (2.0 * steps[j]);
        jac.set_column(j, &d);
    }
    jac
}

/// Wrap an angle to `(-π, π]`.
pub fn wrap_pi(a: f64) -> f64 {
    let two_pi = std::f64::consts::TAU;
    let mut w = a % two_pi;
    if w > std::f64::consts::PI {
        w -= two_pi;
    } else if w <= -std::f64::consts::PI {
        w += two_pi;
    }
    w
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn cross_follows_right_hand_rule() {
        let x = [1.0, 0.0, 0.0];
        let y = [0.0, 1.0, 0.0];
        assert_eq!(cross(&x, &y), [0.0, 0.0, 1.0]);
    }

    #[test]
    fn ad_matches_fd_on_polynomial() {
        let x = SVector::<f64, 2>::new(1.5, -0.7);
        let (v, j) = ad_jacobian(|x| SVector::from([x[0] * x[1] * x[1], x[0].sin()]), &x);
        let fd = fd_jacobian(
            |x| SVector::from([x[0] * x[1] * x[1], x[0].sin()]),
            &x,
            &SVector::from([1e-6, 1e-6]),
        );
        assert!((v[0] - 1.5 * 0.49).abs() < 1e-15);
        assert!((j - fd).abs().max() < 1e-8);
    }

    #[test]
    fn wrap_pi_range() {
        assert!((wrap_pi(3.0 * std::f64::consts::PI) - std::f64::consts::PI).abs() < 1e-12);
        assert!((wrap_pi(-0.5) + 0.5).abs() < 1e-15);
    }
}
