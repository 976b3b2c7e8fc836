//! Fixed-step classical Runge–Kutta (RK4) integration.

use crate::math::Real;
use nalgebra::SVector;

/// One classical RK4 step of `ẋ = f(x)` with step `h`.
///
/// Fixed-step RK4 is the truth integrator of every scenario (step from the scenario file) and the
/// filters' mean propagator, so truth and filter share one discretisation.
#[inline]
pub fn rk4_step<const N: usize>(
    f: impl Fn(&SVector<f64, N>) -> SVector<f64, N>,
    x: &SVector<f64, N>,
    h: f64,
) -> SVector<f64, N> {
    let k1 = f(x);
    let k2 = f(&(x + k1 * (0.5 * h)));
    let k3 = f(&(x + k2 * (0.5 * h)));
    let k4 = f(&(x + k3 * h));
    x + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0)
}

/// One RK4 step in any [`Real`] scalar: with dual numbers seeded on `x`, the derivative part of the
/// result is the exact state-transition matrix of the discrete step (used by the EKF).
#[inline]
pub fn rk4_step_generic<T: Real, const N: usize>(
    f: impl Fn(&SVector<T, N>) -> SVector<T, N>,
    x: &SVector<T, N>,
    h: f64,
) -> SVector<T, N> {
    let half = T::from(0.5 * h);
    let full = T::from(h);
    let k1 = f(x);
    let k2 = f(&x.zip_map(&k1, |a, b| a + b * half));
    let k3 = f(&x.zip_map(&k2, |a, b| a + b * half));
    let k4 = f(&x.zip_map(&k3, |a, b| a + b * full));
    let sixth = T::from(h / 6.0);
    SVector::from_fn(|i, _| x[i] + (k1[i] + (k2[i] + k3[i]) * 2.0 + k4[i]) * sixth)
}

/// Integrate from 0 to `duration` with at most step `h`, ending exactly at `duration`.
pub fn rk4_integrate<const N: usize>(
    f: impl Fn(&SVector<f64, N>) -> SVector<f64, N>,
    x0: &SVector<f64, N>,
    h: f64,
    duration: f64,
) -> SVector<f64, N> {
    let steps = (duration / h).ceil().max(1.0) as usize;
    let hh = duration / steps as f64;
    let mut x = *x0;
    for _ in 0..steps {
        x = rk4_step(&f, &x, hh);
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rk4_is_fourth_order_on_exponential_decay() {
        let f = |x: &SVector<f64, 1>| -*x;
        let x0 = SVector::<f64, 1>::new(1.0);
        let e1 = (rk4_integrate(f, &x0, 0.1, 1.0)[0] - (-1.0f64).exp()).abs();
        let e2 = (rk4_integrate(f, &x0, 0.05, 1.0)[0] - (-1.0f64).exp()).abs();
        let order = (e1 / e2).log2();
        assert!((order - 4.0).abs() < 0.2, "observed order {order}");
    }
}
