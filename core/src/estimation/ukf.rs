//! Scaled unscented Kalman filter with the Schmidt (consider) update — the USKF of seed 001
//! §IV.B, eq. 39–68.
//!
//! The state is the *augmented* vector of seed 001 eq. 39–40: the last `n_consider` components
//! are consider parameters, `L = N` counts them. Sigma points are redrawn from the current
//! estimate before every step (eq. 41–43), both for the time update (eq. 44–47) and for the
//! measurement update (eq. 61–65, "sigma points are calculated around the prior estimate").
//! Consider parameters are propagated with the rest of the state by `f` and Qₐ (eq. 44–47, 51);
//! only the measurement update treats them differently (eq. 67–68).
//!
//! # Weights and negative `w₀`
//!
//! With λ = α²(L + κ) − L the weights are eq. 48–50. Seed 001's choice α = 1, β = 2, κ = 3 − L
//! ([`UkfParams::SEED001`], the default) gives L + λ = 3, `w_m⁽⁰⁾ = (3 − L)/3` and
//! `w_c⁽⁰⁾ = (9 − L)/3`:
//! * `w_m⁽⁰⁾ < 0` for L > 3 (e.g. −5/3 for L = 8). That is harmless for the mean (eq. 46 is an
//!   affine combination, computed here as `𝒴⁽⁰⁾ + Σᵢ w_m⁽ⁱ⁾ (𝒴⁽ⁱ⁾ − 𝒴⁽⁰⁾)` to avoid cancellation).
//! * Covariances always use `w_c` (eq. 47, 64, 65), about the `w_m` mean. Writing `w` for
//!   eq. 50, the deviations satisfy `w_m⁽⁰⁾ d₀ = −w Σᵢ dᵢ`, and Cauchy–Schwarz gives
//!   `vᵀ(Σ w_c dᵢdᵢᵀ)v ≥ 0` for every map whenever `g = (w_m⁽⁰⁾)² + w_c⁽⁰⁾(1 − w_m⁽⁰⁾) ≥ 0`,
//!   which holds for all β ≥ α² (then g ≥ 1). Seed 001's constants give g = 2 − w_m⁽⁰⁾ > 0, so
//!   although `w_c⁽⁰⁾ < 0` for L ≥ 10, P⁻ ⪰ Q and S ⪰ R for any f, h, and P⁺ (a Schur
//!   complement of the joint (𝒳, 𝒴) covariance) stays positive definite up to round-off.
//! * With β < α² and `w_m⁽⁰⁾ < 0` (e.g. α = 1, β = 0, κ < 0) g < 0 and P⁻ or S *can* be
//!   indefinite for nonlinear maps. The filter then returns
//!   [`EstimationError::NotPositiveDefinite`] and leaves its state untouched; it does **not**
//!   repair the matrix (no eigenvalue clipping, no switch to a positive `w₀`).
//! * Small α (e.g. 10⁻³ with κ = 0) makes `|w₀| ~ 1/α²`; the moments are then accurate only to
//!   about `ε/α²` relative.
//!
//! Seed 001 eq. 42–43 print `√(L + λP)`; the intended square root is of `(L + λ)P`, taken here
//! as the lower Cholesky factor.

use super::{EstimationError, check_covariance, symmetrize};
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

fn non_finite(what: impl Into<String>) -> EstimationError {
    EstimationError::NonFinite { what: what.into() }
}

fn not_pd(what: impl Into<String>) -> EstimationError {
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
fn measurement_moments<const N: usize>(
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

/// Result of one measurement update.
#[derive(Debug, Clone, PartialEq)]
pub struct UkfUpdate {
    /// Innovation ν = z − ŷ.
    pub innovation: DVector<f64>,
    /// Innovation covariance S = P_yy (eq. 64, including R).
    pub s: DMatrix<f64>,
    /// Normalised innovation squared νᵀ S⁻¹ ν.
    pub nis: f64,
    /// Predicted measurement ŷ (eq. 63).
    pub predicted: DVector<f64>,
}

/// Reusable buffers for [`Ukf::predict_with`] / [`Ukf::update_with`], sized on first use. With
/// them a step allocates only its outputs and a few m-sized temporaries.
#[derive(Debug, Clone, Default)]
pub struct UkfWorkspace<const N: usize> {
    sigma: SigmaPoints<N>,
    y: DMatrix<f64>,
}

/// Unscented Schmidt–Kalman filter state (seed 001 eq. 39–40): augmented estimate and covariance.
#[derive(Debug, Clone, PartialEq)]
pub struct Ukf<const N: usize> {
    /// Augmented estimate x̂ₐ = [x̂; ĉ] (eq. 39).
    pub x: SVector<f64, N>,
    /// Augmented covariance Pₐ = [[P, C], [Cᵀ, P_c]] (eq. 40).
    pub p: SMatrix<f64, N, N>,
    /// Unscented-transform constants (shared by time and measurement updates).
    pub params: UkfParams,
    /// Number of consider parameters: the last `n_consider` states (0 = standard UKF).
    pub n_consider: usize,
}

impl<const N: usize> Ukf<N> {
    /// Start from `x0`, `p0`. Errors if P0 is not positive definite, `x0` is non-finite,
    /// `n_consider ≥ N`, α ∉ (0, 1] or L + λ ≤ 0.
    pub fn new(
        x0: SVector<f64, N>,
        p0: SMatrix<f64, N, N>,
        params: UkfParams,
        n_consider: usize,
    ) -> Result<Self, EstimationError> {
        params.weights_for(N)?;
        if n_consider >= N {
            return Err(EstimationError::InvalidInput(format!(
                "n_consider = {n_consider} must be below the state dimension {N}"
            )));
        }
        if x0.iter().any(|v| !v.is_finite()) {
            return Err(non_finite("initial state x0"));
        }
        let p = symmetrize(&p0);
        check_covariance(&p, "initial covariance P0")?;
        Ok(Ukf {
            x: x0,
            p,
            params,
            n_consider,
        })
    }

    /// Sigma points about the current estimate (eq. 41–43) with weights eq. 48–50.
    pub fn sigma_points(&self) -> Result<SigmaPoints<N>, EstimationError> {
        SigmaPoints::draw(&self.x, &self.p, &self.params)
    }

    /// Time update, eq. 44–47: `𝒳⁻⁽ⁱ⁾ = f(𝒳⁺⁽ⁱ⁾)`, `x̂⁻ = Σ w_m 𝒳⁻⁽ⁱ⁾`,
    /// `P⁻ = Σ w_c (𝒳⁻⁽ⁱ⁾ − x̂⁻)(·)ᵀ + Q` (Q is the augmented Qₐ of eq. 51).
    /// On error the state is unchanged.
    pub fn predict(
        &mut self,
        f: impl FnMut(&SVector<f64, N>) -> SVector<f64, N>,
        q: &SMatrix<f64, N, N>,
    ) -> Result<(), EstimationError> {
        self.predict_with(&mut UkfWorkspace::default(), f, q)
    }

    /// [`Ukf::predict`] with caller-owned buffers.
    pub fn predict_with(
        &mut self,
        ws: &mut UkfWorkspace<N>,
        mut f: impl FnMut(&SVector<f64, N>) -> SVector<f64, N>,
        q: &SMatrix<f64, N, N>,
    ) -> Result<(), EstimationError> {
        if q.iter().any(|v| !v.is_finite()) {
            return Err(non_finite("process noise Q"));
        }
        ws.sigma.redraw(&self.x, &self.p, &self.params)?;
        for (i, pt) in ws.sigma.points.iter_mut().enumerate() {
            let y = f(pt);
            if y.iter().any(|v| !v.is_finite()) {
                return Err(non_finite(format!("propagated sigma point {i}")));
            }
            *pt = y;
        }
        let x = ws.sigma.mean();
        let p = symmetrize(&(ws.sigma.covariance(&x) + q));
        check_covariance(&p, "predicted covariance")?;
        self.x = x;
        self.p = p;
        Ok(())
    }

    /// Measurement update, eq. 61–68, with `h` returning the predicted measurement vector.
    /// See [`Ukf::update_with`].
    pub fn update(
        &mut self,
        mut h: impl FnMut(&SVector<f64, N>) -> DVector<f64>,
        z: &DVector<f64>,
        r: &DMatrix<f64>,
    ) -> Result<UkfUpdate, EstimationError> {
        let into = |x: &SVector<f64, N>, out: &mut [f64]| {
            let y = h(x);
            if y.len() != out.len() {
                return Err(EstimationError::InvalidInput(format!(
                    "measurement model returned {} values, expected {}",
                    y.len(),
                    out.len()
                )));
            }
            out.copy_from_slice(y.as_slice());
            Ok(())
        };
        self.update_with(&mut UkfWorkspace::default(), into, z, r)
    }

    /// Measurement update with caller-owned buffers; `h(x, out)` writes the `z.len()` predicted
    /// measurements of sigma point `x` into `out`.
    ///
    /// Sigma points are redrawn about the prior (eq. 41–43), then `𝒴⁽ⁱ⁾ = h(𝒳⁽ⁱ⁾)` (eq. 61),
    /// `ŷ = Σ w_m 𝒴⁽ⁱ⁾` (63), `S = Σ w_c (𝒴⁽ⁱ⁾ − ŷ)(·)ᵀ + R` (64),
    /// `P_xy = Σ w_c (𝒳⁽ⁱ⁾ − x̂⁻)(𝒴⁽ⁱ⁾ − ŷ)ᵀ` (65), `K = P_xy S⁻¹ = [K_x; K_c]` (66),
    /// `x̂ₓ⁺ = x̂ₓ⁻ + K_x ν`, `ĉ⁺ = ĉ⁻` (67) and
    /// `P⁺ = P⁻ − [[K_x S K_xᵀ, K_x S K_cᵀ], [K_c S K_xᵀ, 0]]` (68). With `n_consider = 0` this is
    /// the standard `x̂ += K ν`, `P⁺ = P⁻ − K S Kᵀ`. An empty `z` is a no-op. On error the state
    /// is unchanged.
    ///
    /// There is no Joseph form for a sigma-point update: a measurement far more precise than the
    /// prior along some direction (posterior/prior variance near machine ε) can make P⁺ lose
    /// positive definiteness to round-off, which is reported as `NotPositiveDefinite`.
    pub fn update_with(
        &mut self,
        ws: &mut UkfWorkspace<N>,
        mut h: impl FnMut(&SVector<f64, N>, &mut [f64]) -> Result<(), EstimationError>,
        z: &DVector<f64>,
        r: &DMatrix<f64>,
    ) -> Result<UkfUpdate, EstimationError> {
        let m = z.len();
        if r.shape() != (m, m) {
            return Err(EstimationError::InvalidInput(format!(
                "R is {:?}, expected {m}x{m}",
                r.shape()
            )));
        }
        if z.iter().chain(r.iter()).any(|v| !v.is_finite()) {
            return Err(non_finite("measurement z or noise R"));
        }
        if m == 0 {
            let empty = DVector::zeros(0);
            return Ok(UkfUpdate {
                innovation: empty.clone(),
                s: DMatrix::zeros(0, 0),
                nis: 0.0,
                predicted: empty,
            });
        }
        ws.sigma.redraw(&self.x, &self.p, &self.params)?;
        let sp = &ws.sigma;
        if ws.y.shape() != (m, sp.points.len()) {
            ws.y = DMatrix::zeros(m, sp.points.len());
        }
        for (i, (pt, col)) in sp
            .points
            .iter()
            .zip(ws.y.as_mut_slice().chunks_exact_mut(m))
            .enumerate()
        {
            h(pt, col)?;
            if col.iter().any(|v| !v.is_finite()) {
                return Err(non_finite(format!(
                    "predicted measurement of sigma point {i}"
                )));
            }
        }
        let (yhat, s, mut pxy) = measurement_moments(sp, ws.y.as_mut_slice(), r);
        let chol = Cholesky::new(s.clone()).ok_or_else(|| not_pd("innovation covariance S"))?;
        let nu = z - &yhat;
        // With S = L Lᵀ, forward substitution gives B = L⁻¹ P_yx (in place: column k of `pxy`
        // becomes row k of B) and w = L⁻¹ ν. Then K ν = Bᵀ w and K S Kᵀ = Bᵀ B (eq. 66 without
        // forming K), νᵀ S⁻¹ ν = |w|².
        let l = chol.l_dirty();
        let mut wv = nu.clone();
        for k in 0..m {
            let lkk = l[(k, k)];
            let (bk, wk) = (pxy.column(k) / lkk, wv[k] / lkk);
            pxy.set_column(k, &bk);
            wv[k] = wk;
            for i in k + 1..m {
                let lik = l[(i, k)];
                pxy.column_mut(i).axpy(-lik, &bk, 1.0);
                wv[i] -= lik * wk;
            }
        }
        // eq. 67–68: consider rows get no mean update and their own block no update.
        let nx = N - self.n_consider.min(N);
        let mut dx: SVector<f64, N> = &pxy * &wv;
        dx.rows_mut(nx, N - nx).fill(0.0);
        let mut ksk = SMatrix::<f64, N, N>::zeros();
        for b in pxy.column_iter() {
            ksk.ger(1.0, &b, &b, 1.0);
        }
        ksk.view_mut((nx, nx), (N - nx, N - nx)).fill(0.0);
        let (x, p) = (self.x + dx, symmetrize(&self.p) - ksk);
        let nis = wv.norm_squared();
        if x.iter().any(|v| !v.is_finite()) {
            return Err(non_finite("updated state"));
        }
        check_covariance(&p, "updated covariance")?;
        self.x = x;
        self.p = p;
        Ok(UkfUpdate {
            innovation: nu,
            s,
            nis,
            predicted: yhat,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn seed001_defaults_have_negative_mean_weight_for_l_above_three() {
        let (wm0, wc0, wi) = UkfParams::SEED001.weights_for(8).unwrap();
        assert!((wm0 + 5.0 / 3.0).abs() < 1e-15);
        assert!((wc0 - 1.0 / 3.0).abs() < 1e-15);
        assert!((wi - 1.0 / 6.0).abs() < 1e-15);
        assert!(UkfParams::SEED001.weights_for(10).unwrap().1 < 0.0);
    }

    #[test]
    fn measurement_moments_are_exact_for_a_linear_map() {
        let x = SVector::<f64, 3>::new(1.0, -2.0, 0.5);
        let p = SMatrix::<f64, 3, 3>::new(2.0, 0.3, 0.1, 0.3, 1.0, -0.2, 0.1, -0.2, 0.5);
        let h = SMatrix::<f64, 2, 3>::new(1.0, 0.5, 0.0, -1.0, 0.0, 2.0);
        let r = DMatrix::from_row_slice(2, 2, &[0.3, 0.1, 0.1, 0.2]);
        let sp = SigmaPoints::draw(&x, &p, &UkfParams::new(0.5, 2.0, Some(1.0))).unwrap();
        let mut ys: Vec<f64> = sp.points.iter().flat_map(|pt| (h * pt).data.0[0]).collect();
        let (yhat, s, pxy) = measurement_moments(&sp, &mut ys, &r);
        let hp = h * p;
        let s_ref = hp * h.transpose();
        for (i, j) in [(0, 0), (0, 1), (1, 0), (1, 1)] {
            assert!((s[(i, j)] - s_ref[(i, j)] - r[(i, j)]).abs() < 1e-12);
        }
        assert!((yhat[0] - (h * x)[0]).abs() + (yhat[1] - (h * x)[1]).abs() < 1e-12);
        assert!((pxy.transpose() - DMatrix::from_column_slice(2, 3, hp.as_slice())).amax() < 1e-12);
    }
}
