//! LinCov of a Kalman filter on a linear system, with the filter's models allowed to differ
//! from the truth's (wrong F, H, Q, R, start).
//!
//! Truth: x_{k+1} = F_t x_k + w_k, w ~ N(0, Q_t); z_k = H_t x_k + v_k, v ~ N(0, R_t);
//! x_0 ~ N(m_0, P_0,t). Filter (its own models): x̂⁻ = F_f x̂, P⁻ = F_f P F_fᵀ + Q_f;
//! K = P⁻ H_fᵀ (H_f P⁻ H_fᵀ + R_f)⁻¹, x̂⁺ = x̂⁻ + K (z − H_f x̂⁻), P⁺ = (I − K H_f) P⁻ (I − K H_f)ᵀ + K R_f Kᵀ.
//!
//! The joint second moments of X = [x; x̂] propagate in blocks (Maybeck vol. 1 ch. 6, the
//! "truth model / filter model" performance analysis):
//! * time update: C_xx ← F_t C_xx F_tᵀ + Q_t, C_xh ← F_t C_xh F_fᵀ, C_hh ← F_f C_hh F_fᵀ, and the
//!   means m_x ← F_t m_x, m_h ← F_f m_h;
//! * measurement update, with A = I − K H_f and B = K H_t (so x̂⁺ = B x + A x̂⁻ + K v):
//!   C_xh ← C_xx Bᵀ + C_xh Aᵀ, C_hh ← B C_xx Bᵀ + B C_xh Aᵀ + A C_hx Bᵀ + A C_hh Aᵀ + K R_t Kᵀ,
//!   m_h ← B m_x + A m_h.
//!
//! The error e = x̂ − x has the mean-square matrix
//! E[e eᵀ] = C_hh − C_hx − C_xh + C_xx + (m_h − m_x)(m_h − m_x)ᵀ; when every filter model equals
//! the truth's and x̂_0 = m_0, P_0,f = P_0,t, it equals the filter's P (the Kalman filter is exact).

use nalgebra::{SMatrix, SVector};

/// The truth's linear model (N states, M measurements).
#[derive(Debug, Clone, PartialEq)]
pub struct LinearTruthModel<const N: usize, const M: usize> {
    /// Transition F_t.
    pub f: SMatrix<f64, N, N>,
    /// Measurement matrix H_t.
    pub h: SMatrix<f64, M, N>,
    /// Process noise Q_t.
    pub q: SMatrix<f64, N, N>,
    /// Measurement noise R_t.
    pub r: SMatrix<f64, M, M>,
    /// Mean of the initial state m_0.
    pub m0: SVector<f64, N>,
    /// Covariance of the initial state P_0,t.
    pub p0: SMatrix<f64, N, N>,
}

/// The filter's own linear model and start.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearFilterModel<const N: usize, const M: usize> {
    /// Transition F_f.
    pub f: SMatrix<f64, N, N>,
    /// Measurement matrix H_f.
    pub h: SMatrix<f64, M, N>,
    /// Process noise Q_f the filter assumes.
    pub q: SMatrix<f64, N, N>,
    /// Measurement noise R_f the filter assumes.
    pub r: SMatrix<f64, M, M>,
    /// Start estimate x̂_0.
    pub x0: SVector<f64, N>,
    /// Start covariance P_0,f.
    pub p0: SMatrix<f64, N, N>,
}

/// What LinCov predicts at one epoch (after its measurement update).
#[derive(Debug, Clone, PartialEq)]
pub struct LinCovEpoch<const N: usize> {
    /// Epoch index k (1 for the first measurement).
    pub k: usize,
    /// Mean-square matrix of the true estimation error E[e eᵀ], e = x̂ − x.
    pub p_true: SMatrix<f64, N, N>,
    /// Mean error E\[e\].
    pub mean_error: SVector<f64, N>,
    /// The filter's own covariance P.
    pub p_filter: SMatrix<f64, N, N>,
    /// Predicted NEES ratio tr(P⁻¹ E[e eᵀ]) / N (1: the filter's P is right on average; the
    /// mean NEES a Monte Carlo would measure, divided by N).
    pub nees_ratio: f64,
}

/// LinCov of a Kalman filter on a linear system.
#[derive(Debug, Clone, PartialEq)]
pub struct LinearLinCov<const N: usize, const M: usize> {
    truth: LinearTruthModel<N, M>,
    filter: LinearFilterModel<N, M>,
    cxx: SMatrix<f64, N, N>,
    cxh: SMatrix<f64, N, N>,
    chh: SMatrix<f64, N, N>,
    mx: SVector<f64, N>,
    mh: SVector<f64, N>,
    p: SMatrix<f64, N, N>,
    k: usize,
}

impl<const N: usize, const M: usize> LinearLinCov<N, M> {
    /// Start: x_0 ~ N(m_0, P_0,t), x̂_0 deterministic.
    pub fn new(truth: LinearTruthModel<N, M>, filter: LinearFilterModel<N, M>) -> Self {
        LinearLinCov {
            cxx: truth.p0,
            cxh: SMatrix::zeros(),
            chh: SMatrix::zeros(),
            mx: truth.m0,
            mh: filter.x0,
            p: filter.p0,
            truth,
            filter,
            k: 0,
        }
    }

    /// One epoch: time update with both models, then the measurement update with the filter's
    /// gain. `None` if the filter's innovation covariance is singular.
    pub fn step(&mut self) -> Option<LinCovEpoch<N>> {
        let (t, f) = (&self.truth, &self.filter);
        // Time update.
        self.cxx = t.f * self.cxx * t.f.transpose() + t.q;
        self.cxh = t.f * self.cxh * f.f.transpose();
        self.chh = f.f * self.chh * f.f.transpose();
        self.mx = t.f * self.mx;
        self.mh = f.f * self.mh;
        let p_minus = f.f * self.p * f.f.transpose() + f.q;
        // The filter's gain from its own covariance.
        let s = f.h * p_minus * f.h.transpose() + f.r;
        let gain = p_minus * f.h.transpose() * s.try_inverse()?;
        let a = SMatrix::<f64, N, N>::identity() - gain * f.h;
        let b = gain * t.h;
        let chx = self.cxh.transpose();
        let cxh = self.cxx * b.transpose() + self.cxh * a.transpose();
        let chh = b * self.cxx * b.transpose()
            + b * self.cxh * a.transpose()
            + a * chx * b.transpose()
            + a * self.chh * a.transpose()
            + gain * t.r * gain.transpose();
        self.cxh = cxh;
        self.chh = (chh + chh.transpose()) * 0.5;
        self.mh = b * self.mx + a * self.mh;
        self.p = a * p_minus * a.transpose() + gain * f.r * gain.transpose();
        self.k += 1;
        Some(self.epoch())
    }

    /// The current statistics.
    pub fn epoch(&self) -> LinCovEpoch<N> {
        let cov = self.chh - self.cxh.transpose() - self.cxh + self.cxx;
        let mean_error = self.mh - self.mx;
        let p_true = cov + mean_error * mean_error.transpose();
        let nees_ratio = self
            .p
            .try_inverse()
            .map_or(f64::NAN, |pi| (pi * p_true).trace() / N as f64);
        LinCovEpoch {
            k: self.k,
            p_true: (p_true + p_true.transpose()) * 0.5,
            mean_error,
            p_filter: self.p,
            nees_ratio,
        }
    }
}
