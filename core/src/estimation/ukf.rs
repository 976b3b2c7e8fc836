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

use super::covariance::{check_covariance, symmetrize};
use super::error::EstimationError;
pub use super::unscented::{SigmaPoints, UkfParams, UnscentedTransform, unscented_transform};
use super::unscented::{measurement_moments, non_finite, not_pd};
use nalgebra::{Cholesky, DMatrix, DVector, SMatrix, SVector};

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
