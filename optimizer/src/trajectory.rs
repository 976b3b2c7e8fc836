//! The vehicle trajectory the geometry is optimized for: the scenario's nominal truth trajectory
//! sampled at the analysis points of [`entrynav::observability::analysis_points`], with
//! trapezoid weights for time integrals.
//!
//! **Integration rule.** `∫ g dt ≈ Σ_k w_k g(t_k)` with trapezoid weights `w_0 = h_0/2`,
//! `w_k = (h_{k−1} + h_k)/2`, `w_N = h_{N−1}/2`. Over seed 002's 240 s at 1 Hz (241 samples) the
//! weights sum to 240 s, so an integrand bounded by 1 (such as `det(N₃)` of three unit vectors)
//! integrates to at most 240 — the paper's maximum.

use crate::error::OptimizerError;
use entrynav::frames::rotate_z;
use entrynav::observability::{AnalysisPoint, analysis_points};
use entrynav::planet::Planet;
use entrynav::scenario::Scenario;
use std::fmt::Write;

/// Vehicle positions along the nominal trajectory.
#[derive(Debug, Clone, PartialEq)]
pub struct Trajectory {
    /// Sample times \[s\].
    pub times: Vec<f64>,
    /// Vehicle inertial positions \[m\] (the inertial frame coincides with the planet-fixed frame at
    /// t = 0).
    pub positions: Vec<[f64; 3]>,
    /// Trapezoid weights \[s\]; they sum to the duration.
    pub weights: Vec<f64>,
    /// Planet constants.
    pub planet: Planet,
    /// Rotation rate the surface beacons turn with [rad/s] (0 for a non-rotating truth model).
    pub omega: f64,
}

/// Trapezoid weights for sample times `t` (ascending).
pub fn trapezoid_weights(t: &[f64]) -> Vec<f64> {
    let n = t.len();
    let mut w = vec![0.0; n];
    for k in 1..n {
        let h = t[k] - t[k - 1];
        w[k - 1] += 0.5 * h;
        w[k] += 0.5 * h;
    }
    w
}

impl Trajectory {
    /// From analysis points already computed for `scenario`.
    pub fn from_points(scenario: &Scenario, points: &[AnalysisPoint]) -> Trajectory {
        let times: Vec<f64> = points.iter().map(|p| p.t).collect();
        Trajectory {
            weights: trapezoid_weights(&times),
            times,
            positions: points.iter().map(|p| p.position).collect(),
            planet: scenario.planet,
            omega: scenario.truth_model.omega(),
        }
    }

    /// The nominal truth trajectory of `scenario`, sampled every `step_s` seconds.
    pub fn from_scenario(scenario: &Scenario, step_s: f64) -> Result<Trajectory, OptimizerError> {
        let points = analysis_points(scenario, step_s)?;
        if points.len() < 2 {
            return Err(OptimizerError::InvalidInput(format!(
                "scenario '{}' gives {} trajectory sample(s); at least 2 are needed",
                scenario.config.name,
                points.len()
            )));
        }
        Ok(Trajectory::from_points(scenario, &points))
    }

    /// Number of samples.
    pub fn len(&self) -> usize {
        self.times.len()
    }

    /// Whether there are no samples.
    pub fn is_empty(&self) -> bool {
        self.times.is_empty()
    }

    /// Sum of the weights \[s\] (the duration covered).
    pub fn duration(&self) -> f64 {
        self.weights.iter().sum()
    }

    /// Vehicle position in the planet-fixed frame at sample `k` \[m\].
    pub fn fixed_position(&self, k: usize) -> [f64; 3] {
        rotate_z(&self.positions[k], -self.omega * self.times[k])
    }

    /// CSV export for external tools (the scipy benchmark): a `#` header with the planet
    /// constants, then `t_s,x_m,y_m,z_m,weight_s` (inertial positions).
    pub fn to_csv(&self, header: &[(&str, String)]) -> String {
        let mut s = String::new();
        let _ = writeln!(
            s,
            "# entrynav trajectory export (inertial frame, trapezoid weights)"
        );
        let _ = writeln!(s, "# mu_m3s2 = {:e}", self.planet.mu);
        let _ = writeln!(s, "# radius_m = {:e}", self.planet.radius);
        let _ = writeln!(s, "# omega_rad_s = {:e}", self.omega);
        for (k, v) in header {
            let _ = writeln!(s, "# {k} = {v}");
        }
        let _ = writeln!(s, "t_s,x_m,y_m,z_m,weight_s");
        for k in 0..self.len() {
            let p = self.positions[k];
            let _ = writeln!(
                s,
                "{},{:.17e},{:.17e},{:.17e},{}",
                self.times[k], p[0], p[1], p[2], self.weights[k]
            );
        }
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trapezoid_weights_sum_to_the_span() {
        let t: Vec<f64> = (0..=240).map(f64::from).collect();
        let w = trapezoid_weights(&t);
        assert_eq!(w[0], 0.5);
        assert_eq!(w[1], 1.0);
        assert_eq!(w[240], 0.5);
        assert!((w.iter().sum::<f64>() - 240.0).abs() < 1e-12);
    }
}
