//! One local filter's update of the common prior ([`LocalUpdate`], [`local_update`]): the batch
//! EKF update the exact DCIFAIF fusion (`fusion_exact.rs`) and LinCov's fusion recursion build on.

use crate::estimation::error::EstimationError;
use crate::estimation::linearization::LinearizedMeasurement;
use crate::math::all_finite;
use nalgebra::{DMatrix, DVector, SMatrix, SVector};

/// One local filter's update of the common prior: its estimate and gains. The posterior
/// covariance and `A = I − K H` are formed only on demand ([`LocalUpdate::posterior`],
/// [`LocalUpdate::a`]): the exact fusion needs neither when there are no consider states.
pub(crate) struct LocalUpdate<const N: usize> {
    /// Posterior estimate.
    pub x: SVector<f64, N>,
    /// Per channel used: slot, gain column and noise variance.
    pub gains: Vec<(usize, SVector<f64, N>, f64)>,
    /// Per channel used, in the order of `gains`: the measurement Jacobian row h_c (H's row).
    pub rows: Vec<SVector<f64, N>>,
    /// Per channel: slot and the marginal ν²/S of the batch update.
    pub nis_terms: Vec<(usize, f64)>,
    /// νᵀS⁻¹ν of the batch update.
    pub nis: f64,
    /// The number of consider states (zero gain rows): with none, the posterior information is
    /// the prior's plus Σ_c h_c h_cᵀ / r_c (see [`PriorInformation`](super::prior_information::PriorInformation)).
    pub n_consider: usize,
    /// Per channel used: u_c = P h_c (P Hᵀ's columns).
    u: Vec<SVector<f64, N>>,
}

impl<const N: usize> LocalUpdate<N> {
    /// A = I − K H = I − Σ_c k_c h_cᵀ.
    pub fn a(&self) -> SMatrix<f64, N, N> {
        let mut a = SMatrix::<f64, N, N>::identity();
        for ((_, k, _), h) in self.gains.iter().zip(&self.rows) {
            a -= k * h.transpose();
        }
        a
    }

    /// The Joseph posterior A P Aᵀ + K R Kᵀ of the prior covariance `p` the update was made
    /// from, in O(N² m): A P = P − Σ_c k_c u_cᵀ and (A P) Aᵀ = A P − Σ_c (A P h_c) k_cᵀ (the same
    /// product, A never multiplied as an N × N matrix).
    pub fn posterior(&self, p: &SMatrix<f64, N, N>) -> SMatrix<f64, N, N> {
        let mut ap = *p;
        for ((_, k, _), u) in self.gains.iter().zip(&self.u) {
            ap -= k * u.transpose();
        }
        let mut post = ap;
        for ((_, k, _), h) in self.gains.iter().zip(&self.rows) {
            post -= (ap * h) * k.transpose();
        }
        for (_, k, r) in &self.gains {
            post += k * k.transpose() * *r;
        }
        (post + post.transpose()) * 0.5
    }
}

/// Batch EKF update of the common prior (`x`, `p`) with the `items` whose slots are in `mask`,
/// linearised at `x_lin` (the prior itself, or an iterated-EKF iterate: ν = z − h(x_lin) −
/// H (x − x_lin)); the last `n_consider` states get zero gain (Schmidt). `None` when the local has
/// nothing to measure this epoch. Work is O(N² m) for m channels: u_c = P h_c,
/// S = H P Hᵀ + R, K = P Hᵀ S⁻¹.
pub(crate) fn local_update<const N: usize>(
    x: &SVector<f64, N>,
    p: &SMatrix<f64, N, N>,
    x_lin: &SVector<f64, N>,
    items: &[(usize, LinearizedMeasurement<N>)],
    mask: &[usize],
    n_consider: usize,
) -> Result<Option<LocalUpdate<N>>, EstimationError> {
    let mine: Vec<&(usize, LinearizedMeasurement<N>)> =
        items.iter().filter(|(c, _)| mask.contains(c)).collect();
    let m = mine.len();
    if m == 0 {
        return Ok(None);
    }
    let rows: Vec<SVector<f64, N>> = mine.iter().map(|it| it.1.1).collect();
    let offset = x - x_lin;
    let nu = DVector::from_fn(m, |a, _| {
        mine[a].1.2 - mine[a].1.0 - mine[a].1.1.dot(&offset)
    });
    let u: Vec<SVector<f64, N>> = rows.iter().map(|h| p * h).collect();
    let mut s = DMatrix::from_fn(m, m, |a, b| rows[a].dot(&u[b]));
    for (a, it) in mine.iter().enumerate() {
        s[(a, a)] += it.1.3;
    }
    let s_diag: Vec<f64> = (0..m).map(|a| s[(a, a)]).collect();
    let chol = s.cholesky().ok_or(EstimationError::NotPositiveDefinite {
        what: "a local filter's innovation covariance".into(),
    })?;
    let nis = nu.dot(&chol.solve(&nu));
    let s_inv = chol.inverse();
    // K's columns k_c = Σ_b u_b (S⁻¹)_bc, consider rows zero.
    let mut dx = SVector::<f64, N>::zeros();
    let mut gains = Vec::with_capacity(m);
    for (c, it) in mine.iter().enumerate() {
        let mut kc = SVector::<f64, N>::zeros();
        for (b, ub) in u.iter().enumerate() {
            kc += ub * s_inv[(b, c)];
        }
        kc.rows_mut(N - n_consider, n_consider).fill(0.0);
        dx += kc * nu[c];
        gains.push((it.0, kc, it.1.3));
    }
    let x_post = x + dx;
    let update = LocalUpdate {
        x: x_post,
        nis_terms: mine
            .iter()
            .enumerate()
            .map(|(col, it)| (it.0, nu[col] * nu[col] / s_diag[col]))
            .collect(),
        gains,
        rows,
        nis,
        n_consider,
        u,
    };
    // A finite gain on a finite prior gives a finite posterior, except where the prior
    // overflows; the posterior is checked where it is formed.
    if !all_finite(x_post.as_slice())
        || update
            .gains
            .iter()
            .any(|(_, k, _)| !all_finite(k.as_slice()))
    {
        return Err(EstimationError::NonFinite {
            what: "a local filter's update".into(),
        });
    }
    Ok(Some(update))
}
