//! Extended Kalman filter with Joseph-form updates (seed 000 eq. 17–18), optionally in Schmidt
//! consider form: the last `n_consider` states are parameters whose uncertainty enters every gain
//! but which are never updated (Schmidt 1966; Tapley, Schutz & Born, *Statistical Orbit
//! Determination*, §6.4: K_c = 0, covariance by the Joseph form, which holds for any gain).

use super::covariance::{check_covariance, symmetrize};
use super::error::EstimationError;
use super::linearization::{LinearizedMeasurement, linearization_error_values};
use super::propagate::phi_p_phit;
use crate::math::all_finite;
use nalgebra::{SMatrix, SVector};

/// Result of one scalar measurement update.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ScalarInnovation {
    /// Innovation ν = z − ẑ.
    pub nu: f64,
    /// Innovation variance s = h P hᵀ + r.
    pub s: f64,
}

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
        if !all_finite(x_next.as_slice()) {
            return Err(EstimationError::NonFinite {
                what: "predicted state".into(),
            });
        }
        let p = phi_p_phit(phi, &self.p) + q;
        self.x = x_next;
        self.p = symmetrize(&p);
        if !all_finite(self.p.as_slice()) {
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
            || !all_finite(h.as_slice())
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
        // On the column arrays (`c[j][i]` is entry (i, j)), free of per-entry bounds checks.
        let c = &mut self.p.data.0;
        for j in 0..N {
            for i in 0..j + 1 {
                let v = c[j][i] - k[i] * ph[j] - ph[i] * k[j] + k[i] * k[j] * s;
                c[j][i] = v;
                c[i][j] = v;
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

impl<const N: usize> Ekf<N> {
    /// Iterated EKF update (Bell & Cathey 1993: Gauss–Newton on the maximum a posteriori cost
    /// ½‖x − x̂⁻‖²_{P⁻⁻¹} + ½‖z − h(x)‖²_{R⁻¹}). `items` are linearised at the prior; iteration i
    /// relinearises at the iterate x_i (`relinearize`, same channels in the same order) and takes,
    /// from the unchanged prior (x̂⁻, P⁻),
    ///
    /// ```text
    /// x_{i+1} = x̂⁻ + K_i (z − h(x_i) − H_i (x̂⁻ − x_i)),  K_i = P⁻ H_iᵀ (H_i P⁻ H_iᵀ + R)⁻¹,
    /// ```
    ///
    /// at most `iterations` times, stopping early when the linearisation at x_i predicts every
    /// measurement at x_{i+1} to within `tolerance` of its σ (relinearising would change
    /// nothing). The covariance is the Joseph form with the last H_i; consider rows keep zero gain.
    /// One iteration is [`Ekf::update_linearized`]. Returns the per-scalar ν²/s terms and the NIS
    /// of the last pass.
    ///
    /// The stopping test needs only the measurement *values* at the iterate: `values(x)` gives
    /// them (the same channels in the same order, equal to the `.0` of `relinearize(x)`), and the
    /// Jacobians of `relinearize` are computed only when another pass follows — in an entry filter
    /// nearly every epoch stops after the first pass, so this saves an AD linearisation per epoch.
    pub fn update_iterated(
        &mut self,
        items: &[LinearizedMeasurement<N>],
        iterations: usize,
        tolerance: f64,
        mut values: impl FnMut(&SVector<f64, N>) -> Vec<f64>,
        mut relinearize: impl FnMut(&SVector<f64, N>) -> Vec<LinearizedMeasurement<N>>,
    ) -> Result<(Vec<f64>, f64), EstimationError> {
        let prior = self.clone();
        let mut lin = prior.x;
        let mut current = items.to_vec();
        let mut it = 1;
        loop {
            let mut trial = prior.clone();
            let (_, terms, nis) = trial.update_linearized(&lin, &current)?;
            if !all_finite(trial.x.as_slice()) {
                return Err(EstimationError::NonFinite {
                    what: "iterated-EKF iterate".into(),
                });
            }
            let done = it >= iterations || {
                let at_x = values(&trial.x);
                if at_x.len() != current.len() {
                    return Err(EstimationError::InvalidInput(format!(
                        "relinearisation returned {} measurements for {}",
                        at_x.len(),
                        current.len()
                    )));
                }
                let small =
                    linearization_error_values(&lin, &current, &trial.x, &at_x) <= tolerance;
                if !small {
                    let next = relinearize(&trial.x);
                    if next.len() != current.len() {
                        return Err(EstimationError::InvalidInput(format!(
                            "relinearisation returned {} measurements for {}",
                            next.len(),
                            current.len()
                        )));
                    }
                    lin = trial.x;
                    current = next;
                }
                small
            };
            if done {
                *self = trial;
                return Ok((terms, nis));
            }
            it += 1;
        }
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

    /// Range from the origin-free beacon b to a 2-D position x: (h, ∂h/∂x).
    fn range(x: &Vector2<f64>, b: &Vector2<f64>) -> (f64, Vector2<f64>) {
        let d = x - b;
        (d.norm(), d / d.norm())
    }

    fn range_items(x: &Vector2<f64>, z: &[f64; 2], r: f64) -> Vec<LinearizedMeasurement<2>> {
        let beacons = [Vector2::new(0.0, 100.0), Vector2::new(120.0, 0.0)];
        beacons
            .iter()
            .zip(z)
            .map(|(b, zi)| {
                let (h, g) = range(x, b);
                (h, g, *zi, r)
            })
            .collect()
    }

    #[test]
    fn iterated_update_of_a_linear_measurement_is_the_kalman_update() {
        let x0 = Vector2::new(1.0, -2.0);
        let p0 = Matrix2::new(4.0, 1.0, 1.0, 3.0);
        let row = Vector2::new(1.0, 2.0);
        let items = vec![(row.dot(&x0), row, 0.7, 0.5)];
        let mut kalman = Ekf::new(x0, p0).unwrap();
        kalman.update_linearized(&x0, &items).unwrap();
        let mut calls = 0;
        let mut iekf = Ekf::new(x0, p0).unwrap();
        iekf.update_iterated(
            &items,
            10,
            1e-12,
            |x| {
                calls += 1;
                vec![row.dot(x)]
            },
            |x| vec![(row.dot(x), row, 0.7, 0.5)],
        )
        .unwrap();
        // A linear model is predicted exactly: one relinearisation shows it, and the update stops.
        assert_eq!(calls, 1);
        assert!((iekf.x - kalman.x).abs().max() < 1e-12);
        assert!((iekf.p - kalman.p).abs().max() < 1e-12);
    }

    #[test]
    fn iterated_update_converges_to_the_maximum_a_posteriori_estimate() {
        // Two ranges, a prior 30 m off with σ = 40 m and 0.5 m range noise: far from linear.
        let truth = Vector2::new(30.0, 20.0);
        let x0 = Vector2::new(0.0, 0.0);
        let p0 = Matrix2::new(1600.0, 0.0, 0.0, 1600.0);
        let r = 0.25;
        let beacons = [Vector2::new(0.0, 100.0), Vector2::new(120.0, 0.0)];
        let z = [
            range(&truth, &beacons[0]).0 + 0.3,
            range(&truth, &beacons[1]).0 - 0.2,
        ];
        let mut iekf = Ekf::new(x0, p0).unwrap();
        iekf.update_iterated(
            &range_items(&x0, &z, r),
            50,
            1e-10,
            |x| range_items(x, &z, r).iter().map(|it| it.0).collect(),
            |x| range_items(x, &z, r),
        )
        .unwrap();
        // Stationarity of ½‖x − x0‖²_{P0⁻¹} + ½ Σ (z_i − h_i(x))²/r at the result (Gauss–Newton
        // fixed point), with the gradient by central differences of the cost itself.
        let cost = |x: &Vector2<f64>| {
            let d = x - x0;
            let prior = 0.5 * d.dot(&(p0.try_inverse().unwrap() * d));
            let meas: f64 = beacons
                .iter()
                .zip(&z)
                .map(|(b, zi)| (zi - range(x, b).0).powi(2) / (2.0 * r))
                .sum();
            prior + meas
        };
        let e = 1e-5;
        for k in 0..2 {
            let mut xp = iekf.x;
            let mut xm = iekf.x;
            xp[k] += e;
            xm[k] -= e;
            let g = (cost(&xp) - cost(&xm)) / (2.0 * e);
            assert!(g.abs() < 1e-4, "gradient {k} of the MAP cost is {g}");
        }
        // The standard EKF, linearised 36 m from the answer, is not at the optimum.
        let mut ekf = Ekf::new(x0, p0).unwrap();
        ekf.update_linearized(&x0, &range_items(&x0, &z, r))
            .unwrap();
        assert!((ekf.x - iekf.x).norm() > 1.0, "{} vs {}", ekf.x, iekf.x);
        assert!((iekf.x - truth).norm() < 2.0, "{}", iekf.x);
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
