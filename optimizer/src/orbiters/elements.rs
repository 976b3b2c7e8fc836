//! The unknowns of one orbiter on a circular orbit (seed 002 eq. 55–56): (Ω, i, f), their
//! canonical form and the core orbiter they describe.

use crate::error::OptimizerError;
use entrynav::beacons::CircularOrbit;
use entrynav::beacons::Orbiter;
use std::f64::consts::PI;
use std::f64::consts::TAU;

/// The circular-orbit unknowns of one orbiter (radians).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OrbitElements {
    /// Longitude of the ascending node Ω \[rad\].
    pub raan: f64,
    /// Inclination i \[rad\].
    pub inc: f64,
    /// Argument of latitude f at t = 0 \[rad\].
    pub true_anomaly: f64,
}

fn wrap_tau(a: f64) -> f64 {
    let w = a.rem_euclid(TAU);
    if w >= TAU { 0.0 } else { w }
}

impl OrbitElements {
    /// From (Ω, i, f) in degrees.
    pub fn from_degrees(raan_deg: f64, inc_deg: f64, true_anomaly_deg: f64) -> OrbitElements {
        OrbitElements {
            raan: raan_deg.to_radians(),
            inc: inc_deg.to_radians(),
            true_anomaly: true_anomaly_deg.to_radians(),
        }
    }

    /// (Ω, i, f) in degrees.
    pub fn degrees(&self) -> [f64; 3] {
        [
            self.raan.to_degrees(),
            self.inc.to_degrees(),
            self.true_anomaly.to_degrees(),
        ]
    }

    /// The same orbit and phase with Ω, f in [0, 2π) and i in [0, π].
    ///
    /// `(Ω, −i, f)` and `(Ω + π, 2π − i, f + π)` describe the same motion as `(Ω + π, i, f + π)`
    /// and `(Ω, i, f)` respectively (P and Q change sign together), which folds any real
    /// inclination into [0, π].
    pub fn canonical(&self) -> OrbitElements {
        let mut inc = self.inc.rem_euclid(TAU);
        let (mut raan, mut f) = (self.raan, self.true_anomaly);
        if inc > PI {
            inc = TAU - inc;
            raan += PI;
            f += PI;
        }
        OrbitElements {
            raan: wrap_tau(raan),
            inc,
            true_anomaly: wrap_tau(f),
        }
    }

    /// Perifocal unit vectors P, Q of seed 002 eq. 56.
    pub fn basis(&self) -> ([f64; 3], [f64; 3]) {
        let (so, co) = self.raan.sin_cos();
        let (si, ci) = self.inc.sin_cos();
        ([co, so, 0.0], [-so * ci, co * ci, si])
    }

    /// The orbiter as the core library models it (for cross-checks and scenario files).
    pub fn orbiter(
        &self,
        planet: &entrynav::Planet,
        altitude_m: f64,
    ) -> Result<Orbiter, OptimizerError> {
        Ok(Orbiter::from_circular(
            planet,
            &CircularOrbit {
                altitude: altitude_m,
                raan: self.raan,
                inc: self.inc,
                true_anomaly: self.true_anomaly,
            },
        )?)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn canonical_elements_describe_the_same_motion() {
        let planet = entrynav::Planet::MARS;
        let alt = 725e3;
        for el in [
            OrbitElements::from_degrees(10.0, -30.0, 100.0),
            OrbitElements::from_degrees(-50.0, 250.0, 700.0),
            OrbitElements::from_degrees(400.0, 90.0, -20.0),
        ] {
            let c = el.canonical();
            assert!((0.0..=PI).contains(&c.inc));
            assert!((0.0..TAU).contains(&c.raan) && (0.0..TAU).contains(&c.true_anomaly));
            let (ra, va) = el.orbiter(&planet, alt).unwrap().initial_state();
            let (rb, vb) = c.orbiter(&planet, alt).unwrap().initial_state();
            for k in 0..3 {
                assert!((ra[k] - rb[k]).abs() < 1e-6, "{el:?} {c:?}");
                assert!((va[k] - vb[k]).abs() < 1e-9);
            }
        }
    }
}
