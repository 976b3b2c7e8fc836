//! Truncated Taylor series ("jets") in one variable, with coefficients in any [`Real`] scalar.
//!
//! A [`Jet<C, K>`] holds the first `K` Taylor coefficients `c[k] = (1/k!)·dᵏy/dtᵏ` at t = 0 of a
//! quantity y(t). Arithmetic and the elementary functions propagate the coefficients *exactly*
//! (the classical Taylor-mode recurrences, e.g. Griewank & Walther, *Evaluating Derivatives*,
//! ch. 13), truncated at degree `K − 1`; no symbolic algebra and no step sizes are involved.
//!
//! `Jet` implements `num_dual::DualNum`, so every model in the crate (written once, generic over
//! [`Real`]) evaluates in it unchanged. With coefficients that are themselves forward-mode dual
//! vectors (`Jet<DualSVec64<N>, K>`) one evaluation carries both the time derivatives along a
//! trajectory and their gradients with respect to the initial state — which is exactly what the
//! rows `∇L_f^k h` of the observability matrix need (seed 002 eq. 9–12; see [`super::lie`]).
//!
//! Comparisons (`<`, `==`) look at the value `c[0]` only, as in `num-dual`, so branches in model
//! code follow the same path as in `f64`.
// Index loops are the clearest way to write the coefficient recurrences (they mirror the formulas).
#![allow(clippy::needless_range_loop)]

use crate::math::Real;
// `num-traits` is not a direct dependency of the core; it is the same crate (0.2) that `num-dual`
// builds on, reached through `rand_distr`'s public re-export.
use rand_distr::num_traits::{FromPrimitive, Inv, Num, One, Signed, Zero};
use std::fmt;
use std::iter::{Product, Sum};
use std::ops::{
    Add, AddAssign, Div, DivAssign, Mul, MulAssign, Neg, Rem, RemAssign, Sub, SubAssign,
};

/// A truncated Taylor series `Σ_{k<K} c[k]·tᵏ` with coefficients of type `C` (`K ≥ 1`).
#[derive(Clone, Copy, Debug)]
pub struct Jet<C, const K: usize> {
    /// Taylor coefficients: `c[k] = (1/k!)·dᵏy/dtᵏ` at t = 0.
    pub c: [C; K],
}

impl<C: Real, const K: usize> Jet<C, K> {
    /// The constant series `re + 0·t + …`.
    #[inline]
    pub fn constant(re: C) -> Self {
        const { assert!(K >= 1, "a jet needs at least one coefficient") };
        let mut c = [C::zero(); K];
        c[0] = re;
        Self { c }
    }

    /// The value `c[0]`.
    #[inline]
    pub fn value(&self) -> C {
        self.c[0]
    }

    /// The k-th time derivative `k!·c[k]` (zero for `k ≥ K`).
    pub fn derivative(&self, k: usize) -> C {
        match self.c.get(k) {
            Some(&ck) => ck * (1..=k).map(|i| i as f64).product::<f64>(),
            None => C::zero(),
        }
    }

    /// The series of `dy/dt` (its top coefficient, unknown at this truncation, is set to zero).
    pub fn time_derivative(&self) -> Self {
        let mut d = [C::zero(); K];
        for k in 0..K.saturating_sub(1) {
            d[k] = self.c[k + 1] * ((k + 1) as f64);
        }
        Self { c: d }
    }

    /// `∫₀ᵗ y' dt + b0` for a series `g` of `dy/da` along `a(t)`: the coefficients of
    /// `b(t) = F(a(t))` from `F(a0) = b0` and `g = F'(a)` (since `b' = g·a'`).
    pub(crate) fn compose_integral(a: &Self, g: &Self, b0: C) -> Self {
        let mut b = [C::zero(); K];
        b[0] = b0;
        for k in 1..K {
            let mut s = C::zero();
            for j in 1..=k {
                s += a.c[j] * g.c[k - j] * (j as f64);
            }
            b[k] = s / (k as f64);
        }
        Self { c: b }
    }

    #[inline]
    fn add_ref(a: &Self, b: &Self) -> Self {
        let mut c = a.c;
        for k in 0..K {
            c[k] += b.c[k];
        }
        Self { c }
    }

    #[inline]
    fn sub_ref(a: &Self, b: &Self) -> Self {
        let mut c = a.c;
        for k in 0..K {
            c[k] -= b.c[k];
        }
        Self { c }
    }

    /// Cauchy product, truncated.
    #[inline]
    fn mul_ref(a: &Self, b: &Self) -> Self {
        let mut c = [C::zero(); K];
        for k in 0..K {
            let mut s = a.c[0] * b.c[k];
            for i in 1..=k {
                s += a.c[i] * b.c[k - i];
            }
            c[k] = s;
        }
        Self { c }
    }

    /// `q = a/b`: `q_k = (a_k − Σ_{j=1..k} b_j q_{k−j}) / b_0`.
    #[inline]
    fn div_ref(a: &Self, b: &Self) -> Self {
        let inv = b.c[0].recip();
        let mut q = [C::zero(); K];
        for k in 0..K {
            let mut s = a.c[k];
            for j in 1..=k {
                s -= b.c[j] * q[k - j];
            }
            q[k] = s * inv;
        }
        Self { c: q }
    }

    /// `a mod b` with the derivative of `a − b·trunc(a0/b0)` (the quotient is locally constant).
    fn rem_ref(a: &Self, b: &Self) -> Self {
        let n = (a.c[0].re() / b.c[0].re()).trunc();
        Self::sub_ref(a, &b.scale_f64(n))
    }

    #[inline]
    pub(crate) fn scale_f64(&self, s: f64) -> Self {
        let mut c = self.c;
        for ck in c.iter_mut() {
            *ck *= s;
        }
        Self { c }
    }
}

/// `impl Op` for all four owned/borrowed combinations from one `fn(&Jet, &Jet) -> Jet`.
macro_rules! jet_binop {
    ($trt:ident, $mth:ident, $imp:ident, $atrt:ident, $amth:ident) => {
        impl<C: Real, const K: usize> $trt<&Jet<C, K>> for &Jet<C, K> {
            type Output = Jet<C, K>;
            #[inline]
            fn $mth(self, rhs: &Jet<C, K>) -> Jet<C, K> {
                Jet::$imp(self, rhs)
            }
        }
        impl<C: Real, const K: usize> $trt<Jet<C, K>> for &Jet<C, K> {
            type Output = Jet<C, K>;
            #[inline]
            fn $mth(self, rhs: Jet<C, K>) -> Jet<C, K> {
                Jet::$imp(self, &rhs)
            }
        }
        impl<C: Real, const K: usize> $trt<&Jet<C, K>> for Jet<C, K> {
            type Output = Jet<C, K>;
            #[inline]
            fn $mth(self, rhs: &Jet<C, K>) -> Jet<C, K> {
                Jet::$imp(&self, rhs)
            }
        }
        impl<C: Real, const K: usize> $trt for Jet<C, K> {
            type Output = Jet<C, K>;
            #[inline]
            fn $mth(self, rhs: Jet<C, K>) -> Jet<C, K> {
                Jet::$imp(&self, &rhs)
            }
        }
        impl<C: Real, const K: usize> $atrt for Jet<C, K> {
            #[inline]
            fn $amth(&mut self, rhs: Jet<C, K>) {
                *self = Jet::$imp(self, &rhs);
            }
        }
    };
}

jet_binop!(Add, add, add_ref, AddAssign, add_assign);
jet_binop!(Sub, sub, sub_ref, SubAssign, sub_assign);
jet_binop!(Mul, mul, mul_ref, MulAssign, mul_assign);
jet_binop!(Div, div, div_ref, DivAssign, div_assign);
jet_binop!(Rem, rem, rem_ref, RemAssign, rem_assign);

impl<C: Real, const K: usize> Add<f64> for Jet<C, K> {
    type Output = Self;
    #[inline]
    fn add(mut self, rhs: f64) -> Self {
        self.c[0] += rhs;
        self
    }
}
impl<C: Real, const K: usize> Sub<f64> for Jet<C, K> {
    type Output = Self;
    #[inline]
    fn sub(mut self, rhs: f64) -> Self {
        self.c[0] -= rhs;
        self
    }
}
impl<C: Real, const K: usize> Mul<f64> for Jet<C, K> {
    type Output = Self;
    #[inline]
    fn mul(self, rhs: f64) -> Self {
        self.scale_f64(rhs)
    }
}
impl<C: Real, const K: usize> Div<f64> for Jet<C, K> {
    type Output = Self;
    #[inline]
    fn div(self, rhs: f64) -> Self {
        self.scale_f64(rhs.recip())
    }
}
impl<C: Real, const K: usize> Rem<f64> for Jet<C, K> {
    type Output = Self;
    #[inline]
    fn rem(self, rhs: f64) -> Self {
        Jet::rem_ref(&self, &Jet::from(rhs))
    }
}
impl<C: Real, const K: usize> AddAssign<f64> for Jet<C, K> {
    #[inline]
    fn add_assign(&mut self, rhs: f64) {
        self.c[0] += rhs;
    }
}
impl<C: Real, const K: usize> SubAssign<f64> for Jet<C, K> {
    #[inline]
    fn sub_assign(&mut self, rhs: f64) {
        self.c[0] -= rhs;
    }
}
impl<C: Real, const K: usize> MulAssign<f64> for Jet<C, K> {
    #[inline]
    fn mul_assign(&mut self, rhs: f64) {
        *self = self.scale_f64(rhs);
    }
}
impl<C: Real, const K: usize> DivAssign<f64> for Jet<C, K> {
    #[inline]
    fn div_assign(&mut self, rhs: f64) {
        *self = self.scale_f64(rhs.recip());
    }
}
impl<C: Real, const K: usize> RemAssign<f64> for Jet<C, K> {
    #[inline]
    fn rem_assign(&mut self, rhs: f64) {
        *self = Jet::rem_ref(self, &Jet::from(rhs));
    }
}

impl<C: Real, const K: usize> Neg for Jet<C, K> {
    type Output = Self;
    #[inline]
    fn neg(self) -> Self {
        self.scale_f64(-1.0)
    }
}
impl<C: Real, const K: usize> Neg for &Jet<C, K> {
    type Output = Jet<C, K>;
    #[inline]
    fn neg(self) -> Jet<C, K> {
        self.scale_f64(-1.0)
    }
}

impl<C: Real, const K: usize> From<f64> for Jet<C, K> {
    #[inline]
    fn from(v: f64) -> Self {
        Self::constant(C::from(v))
    }
}

impl<C: Real, const K: usize> Zero for Jet<C, K> {
    #[inline]
    fn zero() -> Self {
        Self::constant(C::zero())
    }
    #[inline]
    fn is_zero(&self) -> bool {
        self.c.iter().all(|c| c.is_zero())
    }
}

impl<C: Real, const K: usize> One for Jet<C, K> {
    #[inline]
    fn one() -> Self {
        Self::constant(C::one())
    }
}

impl<C: Real, const K: usize> Num for Jet<C, K> {
    type FromStrRadixErr = <f64 as Num>::FromStrRadixErr;
    fn from_str_radix(s: &str, radix: u32) -> Result<Self, Self::FromStrRadixErr> {
        <f64 as Num>::from_str_radix(s, radix).map(Self::from)
    }
}

impl<C: Real, const K: usize> Signed for Jet<C, K> {
    fn abs(&self) -> Self {
        if self.is_negative() { -self } else { *self }
    }
    fn abs_sub(&self, other: &Self) -> Self {
        if self.c[0].re() > other.c[0].re() {
            self - other
        } else {
            Self::zero()
        }
    }
    fn signum(&self) -> Self {
        Self::from(self.c[0].re().signum() * f64::from(self.c[0].re() != 0.0))
    }
    fn is_positive(&self) -> bool {
        self.c[0].re() > 0.0
    }
    fn is_negative(&self) -> bool {
        self.c[0].re() < 0.0
    }
}

impl<C: Real, const K: usize> Inv for Jet<C, K> {
    type Output = Self;
    fn inv(self) -> Self {
        Jet::div_ref(&Self::one(), &self)
    }
}

impl<C: Real, const K: usize> Sum for Jet<C, K> {
    fn sum<I: Iterator<Item = Self>>(iter: I) -> Self {
        iter.fold(Self::zero(), |a, b| a + b)
    }
}

impl<'a, C: Real, const K: usize> Sum<&'a Jet<C, K>> for Jet<C, K> {
    fn sum<I: Iterator<Item = &'a Jet<C, K>>>(iter: I) -> Self {
        iter.fold(Self::zero(), |a, b| a + b)
    }
}

impl<C: Real, const K: usize> Product for Jet<C, K> {
    fn product<I: Iterator<Item = Self>>(iter: I) -> Self {
        iter.fold(Self::one(), |a, b| a * b)
    }
}

impl<C: Real, const K: usize> FromPrimitive for Jet<C, K> {
    fn from_i64(n: i64) -> Option<Self> {
        Some(Self::from(n as f64))
    }
    fn from_u64(n: u64) -> Option<Self> {
        Some(Self::from(n as f64))
    }
    fn from_f64(n: f64) -> Option<Self> {
        Some(Self::from(n))
    }
}

/// Like `num-dual`, equality and order look at the value only.
impl<C: Real, const K: usize> PartialEq for Jet<C, K> {
    fn eq(&self, other: &Self) -> bool {
        self.c[0] == other.c[0]
    }
}
impl<C: Real, const K: usize> PartialEq<f64> for Jet<C, K> {
    fn eq(&self, other: &f64) -> bool {
        self.c[0].re() == *other
    }
}
impl<C: Real, const K: usize> PartialOrd for Jet<C, K> {
    fn partial_cmp(&self, other: &Self) -> Option<std::cmp::Ordering> {
        self.c[0].partial_cmp(&other.c[0])
    }
}
impl<C: Real, const K: usize> PartialOrd<f64> for Jet<C, K> {
    fn partial_cmp(&self, other: &f64) -> Option<std::cmp::Ordering> {
        self.c[0].re().partial_cmp(other)
    }
}

impl<C: Real, const K: usize> fmt::Display for Jet<C, K> {
    fn fmt(&self, f: &mut fmt::Formatter) -> fmt::Result {
        write!(f, "{}", self.c[0])?;
        for (k, c) in self.c.iter().enumerate().skip(1) {
            write!(f, " + ({c})·t^{k}")?;
        }
        Ok(())
    }
}
