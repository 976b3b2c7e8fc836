//! The similarity-scaled problem of covariance intersection (see [`super::ci`]'s numerics):
//! `P'_i = D P_i D`, `D = diag(1/√p̄_k)`, the scaled information matrices, Cholesky inverses, and
//! the errors CI reports.

use super::covariance::symmetrize;
use super::error::EstimationError;
use super::spd::{cholesky, inverse_from_cholesky};
use crate::math::all_finite;
use nalgebra::{SMatrix, SVector};

/// A square matrix of the state size.
pub(super) type Mat<const N: usize> = SMatrix<f64, N, N>;
/// A vector of the state size.
pub(super) type Vect<const N: usize> = SVector<f64, N>;

/// A non-finite CI quantity.
pub(super) fn nonfinite(what: String) -> EstimationError {
    EstimationError::NonFinite { what }
}
/// A CI matrix that is not positive definite.
pub(super) fn not_pd(what: String) -> EstimationError {
    EstimationError::NotPositiveDefinite { what }
}
/// CI inputs that do not fit together.
pub(super) fn invalid<T>(msg: String) -> Result<T, EstimationError> {
    Err(EstimationError::InvalidInput(msg))
}

/// Symmetrise, check finite and positive definite, and invert by Cholesky.
pub(super) fn spd_inverse<const N: usize>(
    m: &Mat<N>,
    what: impl Fn() -> String,
) -> Result<Mat<N>, EstimationError> {
    if !all_finite(m.as_slice()) {
        return Err(nonfinite(what()));
    }
    let chol = cholesky(&symmetrize(m)).ok_or_else(|| not_pd(what()))?;
    let inv = inverse_from_cholesky(chol.l_dirty());
    if !all_finite(inv.as_slice()) {
        return Err(not_pd(what()));
    }
    Ok(inv)
}

/// Scale vector `s = diag(D)`, `s_k = 1/√p̄_k`, from the summed covariance diagonals.
pub(super) fn scale_from<const N: usize>(
    pdiag_sum: &Vect<N>,
    n: usize,
) -> Result<Vect<N>, EstimationError> {
    if pdiag_sum.iter().any(|p| *p <= 0.0) {
        return Err(not_pd("CI covariance (non-positive variance)".into()));
    }
    let s = pdiag_sum.map(|p| 1.0 / (p / n as f64).sqrt());
    match s.iter().all(|v| v.is_finite() && *v > 0.0) {
        true => Ok(s),
        false => Err(nonfinite("CI scaling (mean variance)".into())),
    }
}

/// `D P D` for a covariance, or `D⁻¹ Y D⁻¹` for an information matrix when `s` is inverted.
pub(super) fn congruence<const N: usize>(m: &Mat<N>, s: &Vect<N>) -> Mat<N> {
    Mat::<N>::from_fn(|r, c| m[(r, c)] * s[r] * s[c])
}

/// Scaled information matrices `Y'_i = (D P_i D)⁻¹` plus the scale vector, from covariances.
pub(super) fn scaled_infos<const N: usize>(
    estimates: &[(Vect<N>, Mat<N>)],
) -> Result<(Vec<Mat<N>>, Vect<N>), EstimationError> {
    if estimates.is_empty() {
        return invalid("CI needs at least one estimate".into());
    }
    let mut dsum = Vect::<N>::zeros();
    for (i, (x, p)) in estimates.iter().enumerate() {
        if !(all_finite(x.as_slice()) && all_finite(p.as_slice())) {
            return Err(nonfinite(format!("CI estimate {i}")));
        }
        dsum += p.diagonal();
    }
    let s = scale_from(&dsum, estimates.len())?;
    let ys = estimates
        .iter()
        .enumerate()
        .map(|(i, (_, p))| spd_inverse(&congruence(p, &s), || format!("CI covariance P_{i}")))
        .collect::<Result<Vec<_>, _>>()?;
    Ok((ys, s))
}
