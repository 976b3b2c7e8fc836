//! Initial orbiter states from orbital elements: classical Keplerian elements (seed 003 Table 3:
//! a 3700 km, e 0, i 90°, ω 0, f 355°, Ω 127.3°) and the circular-orbit parametrisation of seed
//! 002 eq. 55–56.

use crate::math::{add, scale};
use crate::planet::Planet;

/// Classical Keplerian elements of an elliptic orbit (SI: m and rad).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct KeplerElements {
    /// Semi-major axis a \[m\], > 0.
    pub a: f64,
    /// Eccentricity e ∈ [0, 1).
    pub e: f64,
    /// Inclination i \[rad\].
    pub inc: f64,
    /// Right ascension (longitude) of the ascending node Ω \[rad\].
    pub raan: f64,
    /// Argument of periapsis ω \[rad\].
    pub argp: f64,
    /// True anomaly f at t = 0 \[rad\].
    pub true_anomaly: f64,
}

/// Perifocal unit vectors P (towards periapsis) and Q (90° ahead in the orbit plane).
///
/// With ω = 0 these are exactly seed 002 eq. 56: `P = [cos Ω, sin Ω, 0]`,
/// `Q = [−sin Ω cos i, cos Ω cos i, sin i]`.
fn perifocal_basis(raan: f64, inc: f64, argp: f64) -> ([f64; 3], [f64; 3]) {
    let (so, co) = raan.sin_cos();
    let (si, ci) = inc.sin_cos();
    let (sw, cw) = argp.sin_cos();
    let p = [co * cw - so * sw * ci, so * cw + co * sw * ci, sw * si];
    let q = [-co * sw - so * cw * ci, -so * sw + co * cw * ci, cw * si];
    (p, q)
}

impl KeplerElements {
    /// Inertial position \[m\] and velocity [m/s] for gravitational parameter `mu`.
    ///
    /// `r = p/(1 + e cos f)`, `r = r (cos f P + sin f Q)`, `v = √(μ/p) (−sin f P + (e + cos f) Q)`
    /// with `p = a(1 − e²)`; for e = 0, ω = 0 this reduces to seed 002 eq. 55. The inputs are not
    /// validated here (see [`super::Orbiter::from_elements`]).
    pub fn to_state(&self, mu: f64) -> ([f64; 3], [f64; 3]) {
        let (p_hat, q_hat) = perifocal_basis(self.raan, self.inc, self.argp);
        let p = self.a * (1.0 - self.e * self.e);
        let (sf, cf) = self.true_anomaly.sin_cos();
        let r = p / (1.0 + self.e * cf);
        let vs = (mu / p).sqrt();
        let pos = add(&scale(r * cf, &p_hat), &scale(r * sf, &q_hat));
        let vel = add(&scale(-vs * sf, &p_hat), &scale(vs * (self.e + cf), &q_hat));
        (pos, vel)
    }
}

/// The circular-orbit parametrisation of seed 002 eq. 55–56 (the optimizer's variables Ω, i, f).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct CircularOrbit {
    /// Altitude above the reference sphere \[m\] (the paper's `a_i`), > 0.
    pub altitude: f64,
    /// Longitude of the ascending node Ω \[rad\].
    pub raan: f64,
    /// Inclination i \[rad\].
    pub inc: f64,
    /// Initial argument of latitude / true anomaly f \[rad\] measured from the ascending node.
    pub true_anomaly: f64,
}

impl CircularOrbit {
    /// Seed 002 eq. 55: `r0 = (R + a) (cos f P + sin f Q)`,
    /// `v0 = √(μ/(R + a)) (−sin f P + cos f Q)`, with P, Q of eq. 56. Not validated here.
    pub fn to_state(&self, planet: &Planet) -> ([f64; 3], [f64; 3]) {
        KeplerElements {
            a: planet.radius + self.altitude,
            e: 0.0,
            inc: self.inc,
            raan: self.raan,
            argp: 0.0,
            true_anomaly: self.true_anomaly,
        }
        .to_state(planet.mu)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_argp_gives_seed002_eq56_basis() {
        let (raan, inc) = (0.7, 1.2);
        let (p, q) = perifocal_basis(raan, inc, 0.0);
        let p56 = [raan.cos(), raan.sin(), 0.0];
        let q56 = [-raan.sin() * inc.cos(), raan.cos() * inc.cos(), inc.sin()];
        for k in 0..3 {
            assert!((p[k] - p56[k]).abs() < 1e-15 && (q[k] - q56[k]).abs() < 1e-15);
        }
    }

    #[test]
    fn periapsis_and_apoapsis_radii() {
        let mu = Planet::MARS.mu;
        let mut el = KeplerElements {
            a: 10e6,
            e: 0.4,
            inc: 0.3,
            raan: 1.0,
            argp: 2.0,
            true_anomaly: 0.0,
        };
        let (r, v) = el.to_state(mu);
        let rn = crate::math::norm(&r);
        assert!((rn - 6e6).abs() < 1e-6);
        // Vis-viva.
        let v2 = crate::math::dot(&v, &v);
        assert!((v2 - mu * (2.0 / rn - 1.0 / el.a)).abs() < 1e-6);
        el.true_anomaly = std::f64::consts::PI;
        assert!((crate::math::norm(&el.to_state(mu).0) - 14e6).abs() < 1e-6);
    }
}
