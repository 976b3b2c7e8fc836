//! Posterior Cramér–Rao lower bound (PCRLB) recursion.
//!
//! Tichavský, Muravchik & Nehorai (1998, IEEE Trans. Signal Processing 46(5), eq. 21): for
//! x_{k+1} = f_k(x_k) + w_k, w_k ~ N(0, Q_k), z_k = h_k(x_k) + v_k, the Bayesian information
//! matrix of x_k obeys
//!
//! ```text
//! J_{k+1} = D²²_k − D²¹_k (J_k + D¹¹_k)⁻¹ D¹²_k,
//! D¹¹ = E[Fᵀ Q⁻¹ F],  D¹² = −E[Fᵀ] Q⁻¹,  D²² = Q⁻¹ + E[Hᵀ R⁻¹ H],   F = ∂f/∂x, H = ∂h/∂x,
//! ```
//!
//! and E[(x̂_k − x_k)(x̂_k − x_k)ᵀ] ⪰ J_k⁻¹ for every estimator. The entry truth has no process
//! noise (Q = 0), where D¹¹ and D²² do not exist; the limit (Ristic, Arulampalam & Gordon,
//! *Beyond the Kalman Filter*, 2004, §4.2) with the expectation of F taken over the trajectories
//! is the covariance-form recursion used here:
//!
//! ```text
//! P⁻_{k+1} = F̄_k P_k F̄_kᵀ + Q_k,   P_{k+1} = (P⁻_{k+1}⁻¹ + Ī_{k+1})⁻¹,   P_0 = J_0⁻¹,
//! ```
//!
//! with F̄ = E(F) and Ī = E(Hᵀ R⁻¹ H) averaged over the Monte Carlo's truth runs (the standard
//! Monte Carlo PCRLB). For a linear-Gaussian system F and H do not depend on the state, the
//! averages are exact, and P_k is the Kalman filter's covariance (a test checks it to 1e-9).
//!
//! The states span many orders of magnitude (rad² beside m²), so the inversions are done on the
//! correlation scale: with D = diag(√P⁻_ii), P = D ((D⁻¹P⁻D⁻¹)⁻¹ + D Ī D)⁻¹ D.
//!
//! Dimensions are known only at run time here (the bound is formed when a study's sums are
//! reported, after runs of a scenario-dependent state size), so this uses dynamic matrices.
//!
//! This is plain matrix numerics (the bottom layer): `sim::bounds::pcrlb` feeds it with Monte Carlo
//! averages along the truth runs, and nothing here knows of scenarios or simulations.

use nalgebra::DMatrix;
use thiserror::Error;

/// Why the recursion could not run.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum RecursionError {
    /// Matrices whose sizes do not fit together.
    #[error("invalid input: {0}")]
    InvalidInput(String),
    /// A matrix or the bound became NaN or infinite.
    #[error("{what} is not finite")]
    NonFinite {
        /// Which quantity (and where).
        what: String,
    },
}

/// One step of the recursion: the transition from the previous epoch, the process noise over it
/// and the expected measurement information at the new epoch.
#[derive(Debug, Clone, PartialEq)]
pub struct BoundStep {
    /// F̄: expected transition matrix from the previous epoch (or from t = 0).
    pub phi: DMatrix<f64>,
    /// Q: process noise over the interval (zero for the entry truth).
    pub q: DMatrix<f64>,
    /// Ī: expected measurement information Hᵀ R⁻¹ H at the epoch.
    pub info: DMatrix<f64>,
}

/// The bound covariance after each step, starting from the prior covariance `p0`.
pub fn pcrlb_recursion(
    p0: &DMatrix<f64>,
    steps: &[BoundStep],
) -> Result<Vec<DMatrix<f64>>, RecursionError> {
    let n = p0.nrows();
    if p0.ncols() != n {
        return Err(RecursionError::InvalidInput(format!(
            "prior covariance is {}x{}, not square",
            n,
            p0.ncols()
        )));
    }
    let mut p = symmetric(p0);
    let mut out = Vec::with_capacity(steps.len());
    for (k, s) in steps.iter().enumerate() {
        for (what, m) in [
            ("transition", &s.phi),
            ("process noise", &s.q),
            ("information", &s.info),
        ] {
            if m.nrows() != n || m.ncols() != n {
                return Err(RecursionError::InvalidInput(format!(
                    "step {k}: {what} matrix is {}x{}, the state has {n}",
                    m.nrows(),
                    m.ncols()
                )));
            }
            if m.iter().any(|v| !v.is_finite()) {
                return Err(RecursionError::NonFinite {
                    what: format!("step {k}: {what} matrix"),
                });
            }
        }
        let prior = symmetric(&(&s.phi * &p * s.phi.transpose() + &s.q));
        p = posterior(&prior, &s.info).ok_or_else(|| RecursionError::NonFinite {
            what: format!("step {k}: bound covariance (prior not positive definite)"),
        })?;
        out.push(p.clone());
    }
    Ok(out)
}

/// (P⁻⁻¹ + I)⁻¹ on the correlation scale of P⁻; `None` when P⁻ is not positive definite.
fn posterior(prior: &DMatrix<f64>, info: &DMatrix<f64>) -> Option<DMatrix<f64>> {
    let n = prior.nrows();
    let d: Vec<f64> = (0..n).map(|i| prior[(i, i)].sqrt()).collect();
    if d.iter().any(|v| !(v.is_finite() && *v > 0.0)) {
        return None;
    }
    let corr = DMatrix::from_fn(n, n, |i, j| prior[(i, j)] / (d[i] * d[j]));
    let info_scaled = DMatrix::from_fn(n, n, |i, j| info[(i, j)] * d[i] * d[j]);
    let corr_inv = corr.cholesky()?.inverse();
    let total = symmetric(&(corr_inv + info_scaled));
    let inv = total.cholesky()?.inverse();
    let p = DMatrix::from_fn(n, n, |i, j| inv[(i, j)] * d[i] * d[j]);
    p.iter().all(|v| v.is_finite()).then(|| symmetric(&p))
}

fn symmetric(m: &DMatrix<f64>) -> DMatrix<f64> {
    (m + m.transpose()) * 0.5
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A Kalman filter on a linear-Gaussian system: its covariance is the PCRLB exactly.
    #[test]
    fn linear_gaussian_bound_is_the_kalman_covariance() {
        let n = 4;
        // Constant-velocity pair with a slow coupling, process noise, and alternating sensors
        // whose scales differ by six orders of magnitude.
        let dt = 0.5;
        let phi = DMatrix::from_row_slice(
            4,
            4,
            &[
                1.0, dt, 0.0, 0.0, //
                0.0, 1.0, 0.0, 1e-3, //
                0.0, 0.0, 1.0, dt, //
                0.0, 0.0, 0.0, 0.98,
            ],
        );
        let q = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(vec![1e-4, 1e-3, 1e-6, 1e-5]));
        let p0 = DMatrix::from_row_slice(
            4,
            4,
            &[
                100.0, 1.0, 0.0, 0.0, //
                1.0, 4.0, 0.0, 0.0, //
                0.0, 0.0, 1e-4, 1e-6, //
                0.0, 0.0, 1e-6, 1e-5,
            ],
        );
        let sensors = [
            (DMatrix::from_row_slice(1, 4, &[1.0, 0.0, 0.0, 0.0]), 2.0),
            (DMatrix::from_row_slice(1, 4, &[0.0, 0.0, 1.0, 0.5]), 1e-6),
            (
                DMatrix::from_row_slice(2, 4, &[1.0, 0.0, 1e3, 0.0, 0.0, 1.0, 0.0, 0.0]),
                0.3,
            ),
        ];
        let mut p = p0.clone();
        let mut steps = Vec::new();
        let mut kalman = Vec::new();
        for k in 0..40 {
            let (h, r) = &sensors[k % sensors.len()];
            let rm = DMatrix::<f64>::identity(h.nrows(), h.nrows()) * *r;
            // Kalman: predict, then the Joseph-form update.
            let pm = &phi * &p * phi.transpose() + &q;
            let s = h * &pm * h.transpose() + &rm;
            let gain = &pm * h.transpose() * s.try_inverse().unwrap();
            let a = DMatrix::<f64>::identity(n, n) - &gain * h;
            p = &a * &pm * a.transpose() + &gain * &rm * gain.transpose();
            kalman.push(p.clone());
            steps.push(BoundStep {
                phi: phi.clone(),
                q: q.clone(),
                info: h.transpose() * rm.try_inverse().unwrap() * h,
            });
        }
        let bound = pcrlb_recursion(&p0, &steps).unwrap();
        for (k, (b, kf)) in bound.iter().zip(&kalman).enumerate() {
            for i in 0..n {
                for j in 0..n {
                    let scale = (kf[(i, i)] * kf[(j, j)]).sqrt();
                    let rel = (b[(i, j)] - kf[(i, j)]).abs() / scale;
                    assert!(
                        rel < 1e-9,
                        "step {k} ({i},{j}): {} vs {}",
                        b[(i, j)],
                        kf[(i, j)]
                    );
                }
            }
        }
    }

    #[test]
    fn deterministic_dynamics_accumulate_information() {
        // Q = 0: a constant observed with unit noise n times has variance 1/(1/p0 + n).
        let p0 = DMatrix::from_element(1, 1, 4.0);
        let step = BoundStep {
            phi: DMatrix::identity(1, 1),
            q: DMatrix::zeros(1, 1),
            info: DMatrix::from_element(1, 1, 1.0),
        };
        let b = pcrlb_recursion(&p0, &vec![step; 10]).unwrap();
        assert!((b[9][(0, 0)] - 1.0 / (0.25 + 10.0)).abs() < 1e-15);
    }

    #[test]
    fn mismatched_or_non_finite_inputs_are_errors() {
        let p0 = DMatrix::identity(2, 2);
        let bad = BoundStep {
            phi: DMatrix::identity(3, 3),
            q: DMatrix::zeros(2, 2),
            info: DMatrix::zeros(2, 2),
        };
        assert!(pcrlb_recursion(&p0, &[bad]).is_err());
        let nan = BoundStep {
            phi: DMatrix::identity(2, 2),
            q: DMatrix::zeros(2, 2),
            info: DMatrix::from_element(2, 2, f64::NAN),
        };
        assert!(pcrlb_recursion(&p0, &[nan]).is_err());
    }
}
