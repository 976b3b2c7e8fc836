//! Extended Kalman filter with Joseph-form updates (seed 000 eq. 17–18), optionally in Schmidt
//! consider form: the last `n_consider` states are parameters whose uncertainty enters every gain
//! but which are never updated (Schmidt 1966; Tapley, Schutz & Born, *Statistical Orbit
//! Determination*, §6.4: K_c = 0, covariance by the Joseph form, which holds for any gain).

use super::{EstimationError, check_covariance, symmetrize};
use nalgebra::{SMatrix, SVector};

/// Result of one scalar measurement update.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScalarInnovation {
    /// Innovation ν = z − ẑ.
    pub nu: f64,
    /// Innovation variance s = h P hᵀ + r.
    pub s: f64,
}

/// A linearised scalar measurement: `(h(x_prior), ∂h/∂x, z, r)`.
pub type LinearizedMeasurement<const N: usize> = (f64, SVector<f64, N>, f64, f64);

/// EKF state: estimate and covariance.
#[derive(Debug, Clone, PartialEq)]
pub struct Ekf<const N: usize> {
    /// Estimate x̂.
    pub x: SVector<f64, N>,
    /// Covariance P.
    pub p: SMatrix<f64, N, N>,
    /// The last `n_consider` states are Schmidt consider parameters (never updated).
    n_consider: usize,
}

impl<const N: usize> Ekf<N> {
    /// Start from `x0`, `p0` (P0 must be positive definite).
    pub fn new(x0: SVector<f64, N>, p0: SMatrix<f64, N, N>) -> Result<Self, EstimationError> {
        check_covariance(&p0, "initial covariance P0")?;
        Ok(Ekf {
            x: x0,
            p: symmetrize(&p0),
            n_consider: 0,
        })
    }

    /// The same filter with its last `n` states as Schmidt consider parameters (at least one
    /// state must stay estimated).
    pub fn with_consider(mut self, n: usize) -> Result<Self, EstimationError> {
        if n >= N {
            return Err(EstimationError::InvalidInput(format!(
                "{n} consider parameters leave no estimated state in a {N}-state filter"
            )));
        }
        self.n_consider = n;
        Ok(self)
    }

    /// Number of consider parameters (the last states).
    pub fn n_consider(&self) -> usize {
        self.n_consider
    }

    /// Time update, seed 000 eq. 17: x̂⁻ = f(x̂⁺) (given), P⁻ = Φ P⁺ Φᵀ + Q.
    pub fn predict(
        &mut self,
        x_next: SVector<f64, N>,
        phi: &SMatrix<f64, N, N>,
        q: &SMatrix<f64, N, N>,
    ) -> Result<(), EstimationError> {
        if x_next.iter().any(|v| !v.is_finite()) {
            return Err(EstimationError::NonFinite {
                what: "predicted state".into(),
            });
        }
        let p = phi * self.p * phi.transpose() + q;
        self.x = x_next;
        self.p = symmetrize(&p);
        if self.p.iter().any(|v| !v.is_finite()) {
            return Err(EstimationError::NonFinite {
                what: "predicted covariance".into(),
            });
        }
        Ok(())
    }

    /// One scalar measurement update in Joseph form (seed 000 eq. 18 with a 1×N `H`):
    ///
    /// ```text
    /// s = h P hᵀ + r,  K = P hᵀ / s (rows of consider states set to 0),  x̂ += K (z − ẑ),
    /// P = (I − K h) P (I − K h)ᵀ + K r Kᵀ
    /// ```
    ///
    /// `predicted` is ẑ. Processing the components of a measurement vector with diagonal R one at a
    /// time, with ẑ_i linearised about the common prior (`ẑ_i = h_i(x̂⁻) + H_i (x̂ − x̂⁻)`), is
    /// algebraically identical to the batch update of eq. 18; see [`Ekf::update_linearized`].
    pub fn update_scalar(
        &mut self,
        predicted: f64,
        h: &SVector<f64, N>,
        z: f64,
        r: f64,
    ) -> Result<ScalarInnovation, EstimationError> {
        if r.is_nan()
            || r <= 0.0
            || !r.is_finite()
            || !z.is_finite()
            || !predicted.is_finite()
            || h.iter().any(|v| !v.is_finite())
        {
            return Err(EstimationError::NonFinite {
                what: "measurement, prediction, Jacobian or noise".into(),
            });
        }
        let ph = self.p * h;
        let s = h.dot(&ph) + r;
        if s.is_nan() || s <= 0.0 {
            return Err(EstimationError::NotPositiveDefinite {
                what: "innovation variance".into(),
            });
        }
        let mut k = ph / s;
        for i in N - self.n_consider..N {
            k[i] = 0.0;
        }
        let nu = z - predicted;
        self.x += k * nu;
        // Joseph form, expanded for a rank-one gain: (I−khᵀ)P(I−khᵀ)ᵀ + k r kᵀ
        //   = P − k (Ph)ᵀ − (Ph) kᵀ + k (hᵀPh + r) kᵀ,
        // evaluated on the upper triangle and mirrored (the result is symmetric by construction).
        for j in 0..N {
            for i in 0..=j {
                let v = self.p[(i, j)] - k[i] * ph[j] - ph[i] * k[j] + k[i] * k[j] * s;
                self.p[(i, j)] = v;
                self.p[(j, i)] = v;
            }
        }
        Ok(ScalarInnovation { nu, s })
    }

    /// Batch-equivalent EKF update of several scalar measurements linearised at the prior `x_prior`:
    /// each item is `(h_i(x_prior), H_i, z_i, r_i)`. Returns the innovations z_i − h_i(x_prior),
    /// the normalised innovation squared of each scalar in the sequence, ν_i²/s_i, and their sum,
    /// the NIS of the whole batch νᵀ S⁻¹ ν (exact for the sequential form).
    pub fn update_linearized(
        &mut self,
        x_prior: &SVector<f64, N>,
        items: &[LinearizedMeasurement<N>],
    ) -> Result<(Vec<f64>, Vec<f64>, f64), EstimationError> {
        let mut nis = 0.0;
        let mut nus = Vec::with_capacity(items.len());
        let mut terms = Vec::with_capacity(items.len());
        for (h0, hrow, z, r) in items {
            let predicted = h0 + hrow.dot(&(self.x - x_prior));
            let inn = self.update_scalar(predicted, hrow, *z, *r)?;
            let term = inn.nu * inn.nu / inn.s;
            nis += term;
            terms.push(term);
            nus.push(*z - h0);
        }
        Ok((nus, terms, nis))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{Matrix2, Vector2};

    #[test]
    fn sequential_scalar_updates_equal_the_batch_kalman_update() {
        let x0 = Vector2::new(1.0, -2.0);
        let p0 = Matrix2::new(4.0, 1.0, 1.0, 3.0);
        let h = nalgebra::Matrix2::new(1.0, 2.0, -1.0, 0.5);
        let r = nalgebra::Matrix2::new(0.5, 0.0, 0.0, 2.0);
        let z = Vector2::new(0.3, 1.7);
        // Batch.
        let s = h * p0 * h.transpose() + r;
        let k = p0 * h.transpose() * s.try_inverse().unwrap();
        let xb = x0 + k * (z - h * x0);
        let ikh = Matrix2::identity() - k * h;
        let pb = ikh * p0 * ikh.transpose() + k * r * k.transpose();
        let nis_b = (z - h * x0).dot(&(s.try_inverse().unwrap() * (z - h * x0)));
        // Sequential.
        let mut f = Ekf::new(x0, p0).unwrap();
        let items: Vec<_> = (0..2)
            .map(|i| {
                let row = Vector2::new(h[(i, 0)], h[(i, 1)]);
                (row.dot(&x0), row, z[i], r[(i, i)])
            })
            .collect();
        let (_, terms, nis) = f.update_linearized(&x0, &items).unwrap();
        assert_eq!(terms.iter().sum::<f64>(), nis);
        assert!((f.x - xb).abs().max() < 1e-12);
        assert!((f.p - pb).abs().max() < 1e-12);
        assert!((nis - nis_b).abs() < 1e-12);
    }

    #[test]
    fn bad_noise_is_an_error_not_a_panic() {
        let mut f = Ekf::new(Vector2::zeros(), Matrix2::identity()).unwrap();
        assert!(
            f.update_scalar(0.0, &Vector2::new(1.0, 0.0), 1.0, 0.0)
                .is_err()
        );
        assert!(
            f.update_scalar(f64::NAN, &Vector2::new(1.0, 0.0), 1.0, 1.0)
                .is_err()
        );
        assert!(Ekf::new(Vector2::zeros(), -Matrix2::identity()).is_err());
    }
}
