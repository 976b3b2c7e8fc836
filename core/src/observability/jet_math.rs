//! Elementary functions of [`Jet`]s: the `num_dual::DualNum` implementation.
//!
//! Every function uses an exact coefficient recurrence (no truncation beyond degree `K − 1`):
//! `exp`, `sin/cos`, `sinh/cosh`, `sqrt` and powers by their own recurrences; the inverse functions
//! and logarithms through `b' = F'(a)·a'` ([`Jet::compose_integral`]).
#![allow(clippy::needless_range_loop)]

use super::jet::Jet;
use crate::math::Real;
use num_dual::{DualNum, DualStruct, Mappable};
use rand_distr::num_traits::One;

impl<C: Real, const K: usize> DualStruct for Jet<C, K> {
    type Real = f64;
    type Inner = C;
    #[inline]
    fn re(&self) -> f64 {
        self.c[0].re()
    }
    #[inline]
    fn from_inner(inner: &C) -> Self {
        Self::constant(*inner)
    }
}

impl<C: Real, const K: usize> Mappable<Self> for Jet<C, K> {
    type Output<O> = O;
    #[inline]
    fn map_dual<G: Fn(Self) -> O, O>(self, g: G) -> O {
        g(self)
    }
}

impl<C: Real, const K: usize> Jet<C, K> {
    /// `(sin a, cos a)` (`hyperbolic = false`) or `(sinh a, cosh a)` (`true`):
    /// `s_k = (1/k) Σ j a_j c_{k−j}`, `c_k = ∓(1/k) Σ j a_j s_{k−j}`.
    fn trig_pair(&self, hyperbolic: bool) -> (Self, Self) {
        let mut s = [C::zero(); K];
        let mut c = [C::zero(); K];
        let a0 = self.c[0];
        (s[0], c[0]) = if hyperbolic {
            (a0.sinh(), a0.cosh())
        } else {
            a0.sin_cos()
        };
        let sign = if hyperbolic { 1.0 } else { -1.0 };
        for k in 1..K {
            let (mut ss, mut cc) = (C::zero(), C::zero());
            for j in 1..=k {
                let ja = self.c[j] * (j as f64);
                ss += ja * c[k - j];
                cc += ja * s[k - j];
            }
            s[k] = ss / (k as f64);
            c[k] = cc * (sign / k as f64);
        }
        (Self { c: s }, Self { c })
    }

    /// `a^p` from `y0 = a0^p` by `a·y' = p·a'·y`:
    /// `y_k = Σ_{j=1..k} (p·j − (k − j)) a_j y_{k−j} / (k·a0)`.
    fn pow_recurrence(&self, p: f64, y0: C) -> Self {
        let mut y = [C::zero(); K];
        y[0] = y0;
        let inv_a0 = self.c[0].recip();
        for k in 1..K {
            let mut s = C::zero();
            for j in 1..=k {
                s += self.c[j] * y[k - j] * (p * j as f64 - (k - j) as f64);
            }
            y[k] = s * inv_a0 / (k as f64);
        }
        Self { c: y }
    }

    /// `1 ∓ a²` style helper: `s + sign·a²`.
    fn shifted_square(&self, s: f64, sign: f64) -> Self {
        (*self * *self) * sign + s
    }
}

impl<C: Real, const K: usize> DualNum for Jet<C, K> {
    type Primitive = f64;
    const NDERIV: usize = C::NDERIV + K - 1;
    type InnerDual = C;

    fn from_re(re: C) -> Self {
        Self::constant(re)
    }

    fn scale(self, factor: &C) -> Self {
        let mut c = self.c;
        for ck in c.iter_mut() {
            *ck *= *factor;
        }
        Self { c }
    }

    fn recip(&self) -> Self {
        Self::one() / *self
    }

    /// Exact integer powers by repeated squaring (valid at a zero value, unlike `powf`).
    fn powi(&self, n: i32) -> Self {
        let mut base = *self;
        let mut e = n.unsigned_abs();
        let mut acc = Self::one();
        while e > 0 {
            if e & 1 == 1 {
                acc *= base;
            }
            e >>= 1;
            if e > 0 {
                base *= base;
            }
        }
        if n < 0 { acc.recip() } else { acc }
    }

    fn powf(&self, n: f64) -> Self {
        if n.fract() == 0.0 && n.abs() <= 64.0 {
            return self.powi(n as i32);
        }
        self.pow_recurrence(n, self.c[0].powf(n))
    }

    fn sqrt(&self) -> Self {
        let mut s = [C::zero(); K];
        s[0] = self.c[0].sqrt();
        let inv2 = (s[0] * 2.0).recip();
        for k in 1..K {
            let mut acc = self.c[k];
            for j in 1..k {
                acc -= s[j] * s[k - j];
            }
            s[k] = acc * inv2;
        }
        Self { c: s }
    }

    fn cbrt(&self) -> Self {
        self.pow_recurrence(1.0 / 3.0, self.c[0].cbrt())
    }

    /// `e_k = (1/k) Σ_{j=1..k} j a_j e_{k−j}`.
    fn exp(&self) -> Self {
        let mut e = [C::zero(); K];
        e[0] = self.c[0].exp();
        for k in 1..K {
            let mut s = C::zero();
            for j in 1..=k {
                s += self.c[j] * e[k - j] * (j as f64);
            }
            e[k] = s / (k as f64);
        }
        Self { c: e }
    }

    fn exp2(&self) -> Self {
        (*self * std::f64::consts::LN_2).exp()
    }

    fn exp_m1(&self) -> Self {
        let mut e = self.exp();
        e.c[0] = self.c[0].exp_m1();
        e
    }

    fn ln(&self) -> Self {
        Self::compose_integral(self, &self.recip(), self.c[0].ln())
    }

    fn log(&self, base: f64) -> Self {
        self.ln() / base.ln()
    }

    fn log2(&self) -> Self {
        self.ln() / std::f64::consts::LN_2
    }

    fn log10(&self) -> Self {
        self.ln() / std::f64::consts::LN_10
    }

    fn ln_1p(&self) -> Self {
        Self::compose_integral(self, &(*self + 1.0).recip(), self.c[0].ln_1p())
    }

    fn sin(&self) -> Self {
        self.trig_pair(false).0
    }

    fn cos(&self) -> Self {
        self.trig_pair(false).1
    }

    fn tan(&self) -> Self {
        let (s, c) = self.trig_pair(false);
        s / c
    }

    fn sin_cos(&self) -> (Self, Self) {
        self.trig_pair(false)
    }

    fn asin(&self) -> Self {
        let g = self.shifted_square(1.0, -1.0).sqrt().recip();
        Self::compose_integral(self, &g, self.c[0].asin())
    }

    fn acos(&self) -> Self {
        let g = -self.shifted_square(1.0, -1.0).sqrt().recip();
        Self::compose_integral(self, &g, self.c[0].acos())
    }

    fn atan(&self) -> Self {
        let g = self.shifted_square(1.0, 1.0).recip();
        Self::compose_integral(self, &g, self.c[0].atan())
    }

    /// `atan2(y = self, x)`: `b' = (x·y' − y·x')/(x² + y²)`.
    fn atan2(&self, other: Self) -> Self {
        let (y, x) = (*self, other);
        let w = (x * y.time_derivative() - y * x.time_derivative()) / (x * x + y * y);
        let mut b = [C::zero(); K];
        b[0] = y.c[0].atan2(x.c[0]);
        for k in 1..K {
            b[k] = w.c[k - 1] / (k as f64);
        }
        Self { c: b }
    }

    fn sinh(&self) -> Self {
        self.trig_pair(true).0
    }

    fn cosh(&self) -> Self {
        self.trig_pair(true).1
    }

    fn tanh(&self) -> Self {
        let (s, c) = self.trig_pair(true);
        s / c
    }

    fn asinh(&self) -> Self {
        let g = self.shifted_square(1.0, 1.0).sqrt().recip();
        Self::compose_integral(self, &g, self.c[0].asinh())
    }

    fn acosh(&self) -> Self {
        let g = self.shifted_square(-1.0, 1.0).sqrt().recip();
        Self::compose_integral(self, &g, self.c[0].acosh())
    }

    fn atanh(&self) -> Self {
        let g = self.shifted_square(1.0, -1.0).recip();
        Self::compose_integral(self, &g, self.c[0].atanh())
    }

    /// `sin x / x`; within machine epsilon of 0 the series `1 − x²/6 + x⁴/120`.
    fn sph_j0(&self) -> Self {
        if self.c[0].re().abs() < f64::EPSILON {
            let x2 = *self * *self;
            Self::one() - x2 / 6.0 + x2 * x2 / 120.0
        } else {
            self.sin() / *self
        }
    }

    /// `(sin x / x − cos x)/x`; near 0 the series `x/3 − x³/30`.
    fn sph_j1(&self) -> Self {
        if self.c[0].re().abs() < f64::EPSILON {
            *self / 3.0 - self.powi(3) / 30.0
        } else {
            let (s, c) = self.sin_cos();
            let rec = self.recip();
            (s * rec - c) * rec
        }
    }

    /// `((3 − x²) sin x − 3x cos x)/x³`; near 0 the series `x²/15 − x⁴/210`.
    fn sph_j2(&self) -> Self {
        if self.c[0].re().abs() < f64::EPSILON {
            let x2 = *self * *self;
            x2 / 15.0 - x2 * x2 / 210.0
        } else {
            let (s, c) = self.sin_cos();
            let x2 = *self * *self;
            ((-x2 + 3.0) * s - *self * c * 3.0) / (*self * x2)
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    type J = Jet<f64, 6>;

    /// `t ↦ a + t` as a jet.
    fn var(a: f64) -> J {
        let mut j = J::constant(a);
        j.c[1] = 1.0;
        j
    }

    #[test]
    fn exp_sin_log_match_closed_form_series() {
        let a = 0.3;
        let e = var(a).exp();
        let (s, c) = var(a).sin_cos();
        let l = var(a).ln();
        let mut fact = 1.0;
        for k in 0..6 {
            if k > 0 {
                fact *= k as f64;
            }
            assert!((e.c[k] - a.exp() / fact).abs() < 1e-14);
            let dsin = [a.sin(), a.cos(), -a.sin(), -a.cos()][k % 4];
            let dcos = [a.cos(), -a.sin(), -a.cos(), a.sin()][k % 4];
            assert!((s.c[k] - dsin / fact).abs() < 1e-14);
            assert!((c.c[k] - dcos / fact).abs() < 1e-14);
            if k > 0 {
                // dᵏ ln / daᵏ = (−1)^{k−1} (k−1)! / aᵏ
                let d = (-1f64).powi(k as i32 - 1) * (fact / k as f64) / a.powi(k as i32);
                assert!((l.c[k] - d / fact).abs() < 1e-11 * d.abs().max(1.0));
            }
        }
    }

    #[test]
    fn inverse_functions_invert() {
        let x = var(0.4);
        for (y, name) in [
            (x.sin().asin(), "asin"),
            (x.cos().acos(), "acos"),
            (x.tan().atan(), "atan"),
            (x.sinh().asinh(), "asinh"),
            (x.tanh().atanh(), "atanh"),
            (x.exp().ln(), "ln"),
            (x.powf(2.5).powf(0.4), "powf"),
            (x.sqrt() * x.sqrt(), "sqrt"),
            (x.cbrt().powi(3), "cbrt"),
            ((x + 1.0).cosh().acosh(), "acosh"),
            (x.sin().atan2(x.cos()), "atan2"),
        ] {
            let shift = if name == "acosh" { 1.0 } else { 0.0 };
            assert!((y.c[0] - 0.4 - shift).abs() < 1e-14, "{name}");
            assert!((y.c[1] - 1.0).abs() < 1e-13, "{name}: {}", y.c[1]);
            for k in 2..6 {
                assert!(y.c[k].abs() < 1e-12, "{name} c{k} = {}", y.c[k]);
            }
        }
    }
}
