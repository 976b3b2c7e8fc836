//! Tabulated density profile: natural cubic spline of ln ρ versus altitude.

use super::density_model::Atmosphere;
use super::error::AtmosphereError;
use crate::math::Real;

/// Minimum number of knots of a [`Tabulated`] profile.
pub const MIN_TABLE_POINTS: usize = 3;

/// Density table interpolated by a natural cubic spline of ln ρ in altitude.
///
/// Seed 001 §V ("trajectory points were interpolated using a cubic spline to determine density
/// values at the query altitude") interpolates its Mars-GRAM profiles this way; we spline ln ρ
/// rather than ρ so that interpolated densities stay positive and an exponential table is
/// reproduced exactly. Natural end conditions: the second derivative of ln ρ is zero at both
/// end knots.
///
/// **Outside the table** (`h` below the first or above the last knot) the profile is extended
/// exponentially: ln ρ continues as a straight line with the spline's log-slope at the end knot,
/// so ρ, dρ/dh and d²ρ/dh² stay continuous. Such extrapolation is only a safety net: callers that
/// must not leave the table check [`Tabulated::covers`] / [`Tabulated::altitude_range`] first.
///
/// Evaluation is generic over [`Real`]: the interval is located with the real part of the
/// altitude and the cubic is evaluated in `T`, so derivatives flow through.
#[derive(Debug, Clone, PartialEq)]
pub struct Tabulated {
    /// Knot altitudes (m), strictly increasing.
    h: Vec<f64>,
    /// ln ρ at the knots.
    y: Vec<f64>,
    /// Per-segment cubic coefficients: ln ρ = y_i + b_i t + c_i t² + d_i t³, t = h − h_i.
    b: Vec<f64>,
    c: Vec<f64>,
    d: Vec<f64>,
    /// d ln ρ / dh at the last knot.
    slope_top: f64,
}

fn invalid(problem: String) -> AtmosphereError {
    AtmosphereError::InvalidTable { problem }
}

impl Tabulated {
    /// Build from knot altitudes (m) and densities (kg/m³).
    ///
    /// Requirements: equal lengths, at least [`MIN_TABLE_POINTS`] points, all values finite,
    /// densities > 0, altitudes strictly monotonic. Strictly *decreasing* altitudes (the usual
    /// order of Mars-GRAM output) are accepted and reversed; repeated altitudes and mixed order are
    /// rejected with an error naming the 1-based point indices.
    pub fn new(alt_m: Vec<f64>, rho: Vec<f64>) -> Result<Tabulated, AtmosphereError> {
        let (mut alt_m, mut rho) = (alt_m, rho);
        if alt_m.len() != rho.len() {
            return Err(invalid(format!(
                "{} altitudes but {} densities",
                alt_m.len(),
                rho.len()
            )));
        }
        if alt_m.len() < MIN_TABLE_POINTS {
            return Err(invalid(format!(
                "{} points, at least {MIN_TABLE_POINTS} are needed",
                alt_m.len()
            )));
        }
        for (i, (&h, &r)) in alt_m.iter().zip(&rho).enumerate() {
            if !h.is_finite() || !r.is_finite() {
                return Err(invalid(format!(
                    "point {}: altitude {h} m, density {r} kg/m³ must be finite",
                    i + 1
                )));
            }
            if r <= 0.0 {
                return Err(invalid(format!(
                    "point {}: density {r} kg/m³ is not positive",
                    i + 1
                )));
            }
        }
        let increasing = alt_m[1] > alt_m[0];
        for i in 1..alt_m.len() {
            let (a, b) = (alt_m[i - 1], alt_m[i]);
            if a == b {
                return Err(invalid(format!(
                    "points {} and {}: altitude {b} m is repeated",
                    i,
                    i + 1
                )));
            }
            if (b > a) != increasing {
                return Err(invalid(format!(
                    "points {} and {}: altitude {b} m after {a} m breaks the {} order",
                    i,
                    i + 1,
                    if increasing {
                        "increasing"
                    } else {
                        "decreasing"
                    }
                )));
            }
        }
        if !increasing {
            alt_m.reverse();
            rho.reverse();
        }
        let y: Vec<f64> = rho.iter().map(|r| r.ln()).collect();
        Ok(Self::from_log_knots(alt_m, y))
    }

    /// Spline through validated knots (strictly increasing `h`, finite `y`, len ≥ 3).
    pub(super) fn from_log_knots(h: Vec<f64>, y: Vec<f64>) -> Tabulated {
        let n = h.len();
        let dx: Vec<f64> = h.windows(2).map(|w| w[1] - w[0]).collect();
        let slope: Vec<f64> = (0..n - 1).map(|i| (y[i + 1] - y[i]) / dx[i]).collect();
        // Second derivatives m_i; natural: m_0 = m_{n−1} = 0. Thomas algorithm on the interior.
        let mut m = vec![0.0; n];
        let k = n - 2;
        let mut cp = vec![0.0; k];
        let mut rp = vec![0.0; k];
        for j in 0..k {
            let i = j + 1;
            let sub = dx[i - 1];
            let diag = 2.0 * (dx[i - 1] + dx[i]);
            let rhs = 6.0 * (slope[i] - slope[i - 1]);
            // m_0 = 0, so the first row has no sub-diagonal term.
            let (denom, r) = if j == 0 {
                (diag, rhs)
            } else {
                (diag - sub * cp[j - 1], rhs - sub * rp[j - 1])
            };
            cp[j] = dx[i] / denom;
            rp[j] = r / denom;
        }
        // Back substitution; m[n − 1] = 0 closes the recursion.
        for j in (0..k).rev() {
            m[j + 1] = rp[j] - cp[j] * m[j + 2];
        }
        let mut b = Vec::with_capacity(n - 1);
        let mut c = Vec::with_capacity(n - 1);
        let mut d = Vec::with_capacity(n - 1);
        for i in 0..n - 1 {
            b.push(slope[i] - dx[i] * (2.0 * m[i] + m[i + 1]) / 6.0);
            c.push(m[i] / 2.0);
            d.push((m[i + 1] - m[i]) / (6.0 * dx[i]));
        }
        let l = n - 2;
        let slope_top = b[l] + 2.0 * c[l] * dx[l] + 3.0 * d[l] * dx[l] * dx[l];
        Tabulated {
            h,
            y,
            b,
            c,
            d,
            slope_top,
        }
    }

    /// `(lowest, highest)` knot altitude (m).
    pub fn altitude_range(&self) -> (f64, f64) {
        (self.h[0], self.h[self.h.len() - 1])
    }

    /// Whether `[h_min, h_max]` (m) lies inside the table (no extrapolation needed).
    pub fn covers(&self, h_min: f64, h_max: f64) -> bool {
        let (lo, hi) = self.altitude_range();
        h_min >= lo && h_max <= hi && h_min <= h_max
    }

    /// Knot altitudes (m), increasing.
    pub fn altitudes_m(&self) -> &[f64] {
        &self.h
    }

    /// Densities at the knots (kg/m³), in the order of [`Tabulated::altitudes_m`].
    pub fn knot_densities(&self) -> Vec<f64> {
        self.y.iter().map(|y| y.exp()).collect()
    }

    /// Number of knots.
    pub fn num_knots(&self) -> usize {
        self.h.len()
    }

    /// ln ρ at `altitude_m` (spline inside the table, straight-line extension outside).
    pub fn log_density<T: Real>(&self, altitude_m: T) -> T {
        let x = altitude_m.re();
        let n = self.h.len();
        if x.is_nan() || x <= self.h[0] {
            return (altitude_m - self.h[0]) * self.b[0] + self.y[0];
        }
        if x >= self.h[n - 1] {
            return (altitude_m - self.h[n - 1]) * self.slope_top + self.y[n - 1];
        }
        let i = self.h.partition_point(|&k| k <= x) - 1;
        let t = altitude_m - self.h[i];
        ((t * self.d[i] + self.c[i]) * t + self.b[i]) * t + self.y[i]
    }
}

impl Atmosphere for Tabulated {
    /// exp of the ln ρ spline (seed 001 §V cubic-spline interpolation of tabulated profiles).
    fn density<T: Real>(&self, altitude_m: T) -> T {
        self.log_density(altitude_m).exp()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validation_errors_name_points() {
        let e = Tabulated::new(vec![0.0, 1.0], vec![1.0, 0.5]).unwrap_err();
        assert!(e.to_string().contains("at least 3"), "{e}");
        let e = Tabulated::new(vec![0.0, 1.0, 1.0], vec![1.0, 0.5, 0.2]).unwrap_err();
        assert!(e.to_string().contains("points 2 and 3"), "{e}");
        let e = Tabulated::new(vec![0.0, 2.0, 1.0], vec![1.0, 0.5, 0.2]).unwrap_err();
        assert!(e.to_string().contains("increasing"), "{e}");
        let e = Tabulated::new(vec![0.0, 1.0, 2.0], vec![1.0, 0.0, 0.2]).unwrap_err();
        assert!(e.to_string().contains("point 2"), "{e}");
        let e = Tabulated::new(vec![0.0, f64::NAN, 2.0], vec![1.0, 0.1, 0.2]).unwrap_err();
        assert!(e.to_string().contains("finite"), "{e}");
        assert!(Tabulated::new(vec![0.0, 1.0, 2.0], vec![1.0, 0.5]).is_err());
    }

    #[test]
    fn descending_input_is_reversed() {
        let a = Tabulated::new(vec![0.0, 1e3, 3e3, 4e3], vec![1.0, 0.6, 0.3, 0.2]).unwrap();
        let b = Tabulated::new(vec![4e3, 3e3, 1e3, 0.0], vec![0.2, 0.3, 0.6, 1.0]).unwrap();
        assert_eq!(a, b);
        assert_eq!(a.altitude_range(), (0.0, 4e3));
        assert!(a.covers(0.0, 4e3) && !a.covers(-1.0, 10.0) && !a.covers(0.0, 4001.0));
    }

    #[test]
    fn three_point_spline_matches_hand_solution() {
        // y = [0, 1, 0] at x = [0, 1, 2]: m1 = 6·(−1 − 1)/(2·2) = −3.
        let t = Tabulated::new(vec![0.0, 1.0, 2.0], vec![1.0, 1f64.exp(), 1.0]).unwrap();
        // On [0,1]: y = 1.5 t − 0.5 t³ → y(0.5) = 0.75 − 0.0625.
        let y = t.log_density(0.5_f64);
        assert!((y - 0.6875).abs() < 1e-14, "{y}");
        // Ends are natural and extended linearly with slope ±1.5.
        assert!((t.log_density(-1.0_f64) + 1.5).abs() < 1e-14);
        assert!((t.log_density(3.0_f64) + 1.5).abs() < 1e-14);
        assert!(t.log_density(f64::NAN).is_nan());
    }
}
