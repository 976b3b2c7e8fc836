//! The scaled unscented transform of seed 001 §IV.B: its constants and weights (eq. 48–50), the
//! sigma points (eq. 41–43) and the transform of a distribution through a map (eq. 44–47,
//! 61–65). The weights and the treatment of a negative `w₀` are explained in [`super::ukf`].

use super::covariance::symmetrize;
use super::error::EstimationError;
use nalgebra::{Cholesky, Const, DMatrix, DVector, Dyn, OMatrix, SMatrix, SVector};

/// Scaled unscented-transform constants (seed 001 §IV.B, after eq. 43 and eq. 48–50).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct UkfParams {
    /// Spread α of the sigma points, in (0, 1].
    pub alpha: f64,
    /// Prior-distribution constant β (2 is optimal for a Gaussian prior).
    pub beta: f64,
    /// Secondary scaling κ; `None` means κ = 3 − L (seed 001 §IV.B).
    pub kappa: Option<f64>,
}

impl Default for UkfParams {
    fn default() -> Self {
        Self::SEED001
    }
}

/// Scale `L + λ` and the three distinct weights of eq. 48–50.
#[derive(Debug, Clone, Copy)]
struct Weights {
    scale: f64,
    wm0: f64,
    wc0: f64,
    wi: f64,
}

impl UkfParams {
    /// Seed 001's choice: α = 1, β = 2, κ = 3 − L.
    pub const SEED001: UkfParams = UkfParams::new(1.0, 2.0, None);

    /// Constants from α, β and κ (`None` for κ = 3 − L).
    pub const fn new(alpha: f64, beta: f64, kappa: Option<f64>) -> Self {
        UkfParams { alpha, beta, kappa }
    }

    /// κ for dimension `l` (3 − L when unset).
    pub fn kappa(&self, l: usize) -> f64 {
        self.kappa.unwrap_or(3.0 - l as f64)
    }

    /// λ = α²(L + κ) − L.
    pub fn lambda(&self, l: usize) -> f64 {
        self.alpha * self.alpha * (l as f64 + self.kappa(l)) - l as f64
    }

    /// Weights `(w_m⁽⁰⁾, w_c⁽⁰⁾, w⁽ⁱ⁾)` of eq. 48–50 for dimension `l`, after checking
    /// α ∈ (0, 1], finite β and κ, `L ≥ 1` and `L + λ > 0`.
    pub fn weights_for(&self, l: usize) -> Result<(f64, f64, f64), EstimationError> {
        self.weights(l).map(|w| (w.wm0, w.wc0, w.wi))
    }

    fn weights(&self, l: usize) -> Result<Weights, EstimationError> {
        let bad = |m: String| Err(EstimationError::InvalidInput(m));
        if !(self.alpha > 0.0 && self.alpha <= 1.0) {
            return bad(format!("UKF alpha = {} not in (0, 1]", self.alpha));
        }
        let kappa = self.kappa(l);
        if !self.beta.is_finite() || !kappa.is_finite() || l == 0 {
            return bad(format!(
                "UKF beta = {}, kappa = {kappa}, L = {l}",
                self.beta
            ));
        }
        let lambda = self.lambda(l);
        let scale = l as f64 + lambda;
        if !(scale.is_finite() && scale > 0.0) {
            return bad(format!("UKF L + lambda = {scale} must be positive"));
        }
        let wm0 = lambda / scale;
        Ok(Weights {
            scale,
            wm0,
            wc0: wm0 + 1.0 - self.alpha * self.alpha + self.beta,
            wi: 0.5 / scale,
        })
    }
}

/// A set of 2L + 1 sigma points with their mean and covariance weights.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct SigmaPoints<const N: usize> {
    /// Points 𝒳⁽⁰⁾…𝒳⁽²ᴸ⁾ (eq. 41–43): the centre, then `x + Sᵢ`, then `x − Sᵢ`.
    pub points: Vec<SVector<f64, N>>,
    /// Mean weights w_m (eq. 48, 50).
    pub wm: Vec<f64>,
    /// Covariance weights w_c (eq. 49, 50).
    pub wc: Vec<f64>,
}

impl<const N: usize> SigmaPoints<N> {
    /// Sigma points about `x`, `p` (eq. 41–43) with `S Sᵀ = (L + λ) P` by Cholesky.
    pub fn draw(
        x: &SVector<f64, N>,
        p: &SMatrix<f64, N, N>,
        params: &UkfParams,
    ) -> Result<Self, EstimationError> {
        let mut s = Self::default();
        s.redraw(x, p, params)?;
        Ok(s)
    }

    /// As [`SigmaPoints::draw`], reusing this set's buffers (no allocation once sized).
    pub fn redraw(
        &mut self,
        x: &SVector<f64, N>,
        p: &SMatrix<f64, N, N>,
        params: &UkfParams,
    ) -> Result<(), EstimationError> {
        let w = params.weights(N)?;
        if x.iter().chain(p.iter()).any(|v| !v.is_finite()) {
            return Err(non_finite("sigma-point mean or covariance"));
        }
        let sq = Cholesky::new(symmetrize(p) * w.scale)
            .ok_or_else(|| not_pd("covariance (L + lambda) P for the sigma points"))?
            .unpack();
        self.points.clear();
        self.points.push(*x);
        self.points.extend(sq.column_iter().map(|c| x + c));
        self.points.extend(sq.column_iter().map(|c| x - c));
        for (v, w0) in [(&mut self.wm, w.wm0), (&mut self.wc, w.wc0)] {
            v.clear();
            v.push(w0);
            v.resize(2 * N + 1, w.wi);
        }
        Ok(())
    }

    /// Weighted mean Σ w_m⁽ⁱ⁾ 𝒳⁽ⁱ⁾ (eq. 46), in the cancellation-free form
    /// `𝒳⁽⁰⁾ + Σᵢ w_m⁽ⁱ⁾ (𝒳⁽ⁱ⁾ − 𝒳⁽⁰⁾)` (equal because Σ w_m = 1).
    pub fn mean(&self) -> SVector<f64, N> {
        weighted_mean(&self.points, &self.wm)
    }

    /// Weighted covariance Σ w_c⁽ⁱ⁾ (𝒳⁽ⁱ⁾ − x̄)(𝒳⁽ⁱ⁾ − x̄)ᵀ about `mean` (eq. 47 without Q).
    pub fn covariance(&self, mean: &SVector<f64, N>) -> SMatrix<f64, N, N> {
        let mut p = SMatrix::<f64, N, N>::zeros();
        for (x, w) in self.points.iter().zip(&self.wc) {
            let d = x - mean;
            p.ger(*w, &d, &d, 1.0);
        }
        p
    }
}

pub(super) fn non_finite(what: impl Into<String>) -> EstimationError {
    EstimationError::NonFinite { what: what.into() }
}

pub(super) fn not_pd(what: impl Into<String>) -> EstimationError {
    EstimationError::NotPositiveDefinite { what: what.into() }
}

/// `y += a x` on slices.
#[inline(always)]
fn axpy(y: &mut [f64], a: f64, x: &[f64]) {
    y.iter_mut().zip(x).for_each(|(y, x)| *y += a * x);
}

fn weighted_mean<const M: usize>(ys: &[SVector<f64, M>], w: &[f64]) -> SVector<f64, M> {
    let Some(y0) = ys.first() else {
        return SVector::zeros();
    };
    let mut acc = SVector::<f64, M>::zeros();
    for (y, wi) in ys.iter().zip(w).skip(1) {
        acc.axpy(*wi, &(y - y0), 1.0);
    }
    y0 + acc
}

/// P_xy stored N × m, so that its columns (the rows of P_yx) have a fixed size.
type CrossCov<const N: usize> = OMatrix<f64, Const<N>, Dyn>;

/// eq. 63–65 from the sigma points `sp` and their predicted measurements `ys` (column-major
/// m × (2L + 1), column i = 𝒴⁽ⁱ⁾; overwritten with the deviations 𝒴⁽ⁱ⁾ − ŷ): returns ŷ (in the
/// cancellation-free affine form), S = R + Σ w_c dy dyᵀ (symmetric) and P_xy = Σ w_c dx dyᵀ.
pub(super) fn measurement_moments<const N: usize>(
    sp: &SigmaPoints<N>,
    ys: &mut [f64],
    r: &DMatrix<f64>,
) -> (DVector<f64>, DMatrix<f64>, CrossCov<N>) {
    let m = r.nrows();
    let mut yhat = DVector::<f64>::zeros(m);
    for (j, yh) in yhat.iter_mut().enumerate() {
        let y0 = ys[j];
        let cols = ys.chunks_exact(m).zip(&sp.wm).skip(1);
        *yh = y0 + cols.map(|(c, w)| w * (c[j] - y0)).sum::<f64>();
    }
    for col in ys.chunks_exact_mut(m) {
        col.iter_mut().zip(yhat.iter()).for_each(|(c, yh)| *c -= yh);
    }
    let mut s = (r + r.transpose()) * 0.5;
    let mut pxy = CrossCov::<N>::zeros(m);
    for ((dy, pt), w) in ys.chunks_exact(m).zip(&sp.points).zip(&sp.wc) {
        let dx = (pt - sp.points[0]) * *w; // 𝒳⁽⁰⁾ = x̂⁻
        for (b, (col, d)) in s.as_mut_slice().chunks_exact_mut(m).zip(dy).enumerate() {
            axpy(&mut col[b..], w * d, &dy[b..]); // lower triangle only
        }
        for (mut col, d) in pxy.column_iter_mut().zip(dy) {
            col.axpy(*d, &dx, 1.0);
        }
    }
    s.fill_upper_triangle_with_lower_triangle();
    (yhat, s, pxy)
}

/// Mean, covariance and cross-covariance of `g(x)` by the unscented transform.
#[derive(Debug, Clone, PartialEq)]
pub struct UnscentedTransform<const N: usize, const M: usize> {
    /// ȳ = Σ w_m g(𝒳⁽ⁱ⁾) (eq. 46 / 63).
    pub mean: SVector<f64, M>,
    /// P_yy = Σ w_c (g(𝒳⁽ⁱ⁾) − ȳ)(·)ᵀ, without additive noise (eq. 47 / 64).
    pub cov: SMatrix<f64, M, M>,
    /// P_xy = Σ w_c (𝒳⁽ⁱ⁾ − x̄)(g(𝒳⁽ⁱ⁾) − ȳ)ᵀ (eq. 65).
    pub cross: SMatrix<f64, N, M>,
}

/// Push `sigma` through `g` (fixed output size `M`); errors if an output is non-finite.
pub fn unscented_transform<const N: usize, const M: usize>(
    sigma: &SigmaPoints<N>,
    mut g: impl FnMut(&SVector<f64, N>) -> SVector<f64, M>,
) -> Result<UnscentedTransform<N, M>, EstimationError> {
    let mut ys = Vec::with_capacity(sigma.points.len());
    for x in &sigma.points {
        let y = g(x);
        if y.iter().any(|v| !v.is_finite()) {
            return Err(non_finite("unscented-transform output"));
        }
        ys.push(y);
    }
    let (xm, mean) = (sigma.mean(), weighted_mean(&ys, &sigma.wm));
    let mut cov = SMatrix::<f64, M, M>::zeros();
    let mut cross = SMatrix::<f64, N, M>::zeros();
    for ((x, y), w) in sigma.points.iter().zip(&ys).zip(&sigma.wc) {
        let dy = y - mean;
        cov.ger(*w, &dy, &dy, 1.0);
        cross.ger(*w, &(x - xm), &dy, 1.0);
    }
    Ok(UnscentedTransform { mean, cov, cross })
}
