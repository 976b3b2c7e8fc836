//! What LinCov predicts at one epoch ([`EntryLinCovEpoch`]) and the share of the NEES a mean
//! error carries in its onboard covariance.

/// LinCov's prediction at one measurement epoch (after its update).
#[derive(Debug, Clone, PartialEq)]
pub struct EntryLinCovEpoch {
    /// Epoch \[s\].
    pub t: f64,
    /// Predicted RMSE per filter state, √E\[e_i²\] (NaN for a state without truth counterpart).
    pub rmse: Vec<f64>,
    /// Predicted mean error per state E\[e_i\] (the model-mismatch bias).
    pub mean_error: Vec<f64>,
    /// The filter's own σ per state, √P_ii.
    pub sigma: Vec<f64>,
    /// Predicted position RMSE \[m\] (planet-fixed for spherical states, inertial for Cartesian,
    /// as the Monte Carlo's `pos_m`).
    pub pos_m: f64,
    /// Predicted velocity RMSE \[m/s\] (as `vel_mps`).
    pub vel_mps: f64,
    /// The filter's own position σ, √tr(Jₚ P Jₚᵀ) \[m\].
    pub pos_sigma_m: f64,
    /// The filter's own velocity σ \[m/s\].
    pub vel_sigma_mps: f64,
    /// Predicted mean NEES tr(P⁻¹E\[eeᵀ\]) over the states with a truth value.
    pub nees: f64,
    /// Its degrees of freedom.
    pub nees_dof: usize,
    /// The same over the six kinematic states.
    pub nees_kinematic: f64,
    /// The filter's own covariance P along the nominal, N×N row-major: the metric of its NEES.
    pub onboard_cov: Vec<f64>,
}

impl EntryLinCovEpoch {
    /// Predicted mean NEES per degree of freedom, [`Self::nees`] / [`Self::nees_dof`] (compare a
    /// Monte Carlo's `anees / nees_dof`).
    pub fn nees_per_dof(&self) -> f64 {
        self.nees / self.nees_dof.max(1) as f64
    }

    /// The part of the mean NEES that a mean error `mean` carries, m̄ᵀP⁻¹m̄ / dof over the states
    /// with a truth value (E\[eᵀP⁻¹e\] = tr(P⁻¹ Cov e) + m̄ᵀP⁻¹m̄). With LinCov's own
    /// [`Self::mean_error`] it is the predicted bias share of [`Self::nees`] / dof; with a Monte
    /// Carlo's mean error at this epoch it shows how much of that Monte Carlo's NEES is a mean
    /// error (a second-order effect LinCov does not carry when it predicts none). `None` if
    /// `mean` has the wrong length or a needed entry is not finite, or P is not positive
    /// definite over those states.
    pub fn nees_of_mean(&self, mean: &[f64]) -> Option<f64> {
        let n = self.rmse.len();
        if mean.len() != n || self.onboard_cov.len() != n * n {
            return None;
        }
        let idx: Vec<usize> = (0..n).filter(|&i| self.rmse[i].is_finite()).collect();
        if idx.is_empty() || idx.iter().any(|&i| !mean[i].is_finite()) {
            return None;
        }
        let p = |a: usize, b: usize| self.onboard_cov[idx[a] * n + idx[b]];
        let m = idx.len();
        // Scaled to unit diagonal first, as the NEES itself.
        let d: Vec<f64> = (0..m).map(|a| p(a, a).max(0.0).sqrt()).collect();
        if d.iter().any(|v| v.is_nan() || *v <= 0.0) {
            return None;
        }
        let c = nalgebra::DMatrix::from_fn(m, m, |a, b| p(a, b) / (d[a] * d[b]));
        let y = nalgebra::DVector::from_fn(m, |a, _| mean[idx[a]] / d[a]);
        let q = c.cholesky()?.solve(&y).dot(&y) / m as f64;
        q.is_finite().then_some(q)
    }
}

#[cfg(test)]
mod tests {
    use super::EntryLinCovEpoch;
    use nalgebra::{DMatrix, DVector};

    fn epoch(p: &DMatrix<f64>, rmse: Vec<f64>) -> EntryLinCovEpoch {
        let n = p.nrows();
        EntryLinCovEpoch {
            t: 1.0,
            rmse,
            mean_error: vec![0.0; n],
            sigma: vec![0.0; n],
            pos_m: 0.0,
            vel_mps: 0.0,
            pos_sigma_m: 0.0,
            vel_sigma_mps: 0.0,
            nees: 0.0,
            nees_dof: n,
            nees_kinematic: 0.0,
            onboard_cov: p.transpose().iter().copied().collect(),
        }
    }

    /// m̄ᵀP⁻¹m̄/dof against an explicit inverse, on a correlated P with variances 1e-6 to 1e6,
    /// over the states with truth only; refused for a wrong length or a missing entry.
    #[test]
    fn the_mean_errors_nees_is_its_quadratic_form_over_the_states_with_truth() {
        let l = DMatrix::from_fn(4, 4, |r, c| match (r, c) {
            _ if r == c => 10f64.powi(2 * r as i32 - 3),
            _ if r > c => 0.3 * 10f64.powi(r as i32 + c as i32 - 3),
            _ => 0.0,
        });
        let p = &l * l.transpose();
        let m = [2e-3, -0.5, 7.0, 40.0];
        let direct = |idx: &[usize]| {
            let sub = DMatrix::from_fn(idx.len(), idx.len(), |a, b| p[(idx[a], idx[b])]);
            let v = DVector::from_fn(idx.len(), |a, _| m[idx[a]]);
            (v.transpose() * sub.try_inverse().unwrap() * &v)[(0, 0)] / idx.len() as f64
        };
        let all = epoch(&p, vec![1.0; 4]);
        let got = all.nees_of_mean(&m).unwrap();
        assert!((got / direct(&[0, 1, 2, 3]) - 1.0).abs() < 1e-9, "{got}");
        let no_truth_2 = epoch(&p, vec![1.0, 1.0, f64::NAN, 1.0]);
        let mut m_nan = m;
        m_nan[2] = f64::NAN;
        let got = no_truth_2.nees_of_mean(&m_nan).unwrap();
        assert!((got / direct(&[0, 1, 3]) - 1.0).abs() < 1e-9, "{got}");
        assert_eq!(all.nees_of_mean(&m_nan), None);
        assert_eq!(all.nees_of_mean(&m[..3]), None);
    }
}
