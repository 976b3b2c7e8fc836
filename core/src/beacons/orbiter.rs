//! Orbiting beacons in exact two-body motion.
//!
//! The orbiter obeys seed 003 eq. 8 (`ṙ_B = v_B`, `v̇_B = −μ r_B/|r_B|³`), which seed 002 §5.2 and
//! seed 000 ("orbiters follow two-body motion") also assume. Instead of integrating it
//! numerically we propagate analytically with the universal-variable formulation (Bate, Mueller &
//! White §4.4; Curtis §3.7): the universal Kepler equation is solved for the universal anomaly χ
//! and the state follows from the Lagrange coefficients f, g, ḟ, ġ. One formula covers elliptic,
//! parabolic and hyperbolic states.
//!
//! Initial states can be given directly (seed 000 Table 2), as classical elements (seed 003
//! Table 3: a 3700 km, e 0, i 90°, ω 0, f 355°, Ω 127.3°) or in the circular-orbit form of seed
//! 002 eq. 55–56 (see [`super::elements`]).

use super::elements::{CircularOrbit, KeplerElements};
use super::error::{BeaconError, check_finite, check_finite3, check_planet};
use super::motion::BeaconMotion;
use super::stumpff::stumpff;
use crate::math::{add, cross, dot, norm, scale};
use crate::planet::Planet;
use std::f64::consts::TAU;

/// A beacon in exact two-body motion about the planet (seed 003 eq. 8), propagated analytically.
///
/// Everything that does not depend on time is computed once at construction; `state_at` solves
/// the universal Kepler equation by Newton's method safeguarded with bisection (the derivative of
/// the equation is the radius, so it is monotonic and a bracket always exists) and typically
/// converges in 3–6 iterations.
#[derive(Debug, Clone, PartialEq)]
pub struct Orbiter {
    mu: f64,
    sqrt_mu: f64,
    r0: [f64; 3],
    v0: [f64; 3],
    /// |r0| \[m\].
    r0n: f64,
    /// r0·v0/√μ [√m].
    c1: f64,
    /// 1 − α|r0|.
    c2: f64,
    /// α = 1/a = 2/|r0| − |v0|²/μ [1/m] (> 0 elliptic, 0 parabolic, < 0 hyperbolic).
    alpha: f64,
    /// Orbital period for elliptic orbits \[s\].
    period: Option<f64>,
    /// Periapsis radius \[m\] (lower bound on the radius along the conic).
    r_periapsis: f64,
    /// Eccentricity.
    ecc: f64,
}

impl Orbiter {
    /// An orbiter with inertial position `r0` \[m\] and velocity `v0` [m/s] at t = 0
    /// (e.g. seed 000 Table 2, whose planet-frame values are inertial at t = 0).
    ///
    /// Errors: non-finite input, `|r0| ≤ planet.radius`, or a rectilinear state (`r0 × v0 = 0`).
    /// Any conic (elliptic, parabolic, hyperbolic) is accepted.
    pub fn from_state(planet: &Planet, r0: [f64; 3], v0: [f64; 3]) -> Result<Self, BeaconError> {
        check_planet(planet)?;
        check_finite3("orbiter initial position r0 [m]", &r0)?;
        check_finite3("orbiter initial velocity v0 [m/s]", &v0)?;
        let mu = planet.mu;
        let r0n = norm(&r0);
        if r0n <= planet.radius {
            return Err(BeaconError::invalid(
                "orbiter |r0| [m]",
                r0n,
                format!("> planet radius ({} m)", planet.radius),
            ));
        }
        let v0n = norm(&v0);
        let h = norm(&cross(&r0, &v0));
        if h.is_nan() || h <= 1e-10 * r0n * v0n {
            return Err(BeaconError::invalid(
                "orbiter angular momentum |r0 x v0| [m^2/s]",
                h,
                "> 0 (rectilinear states are not supported)",
            ));
        }
        let alpha = 2.0 / r0n - v0n * v0n / mu;
        let p = h * h / mu;
        // e² = 1 − p α, clamped against rounding.
        let ecc = (1.0 - p * alpha).max(0.0).sqrt();
        let period = (alpha > 0.0).then(|| TAU / (mu * alpha * alpha * alpha).sqrt());
        Ok(Orbiter {
            mu,
            sqrt_mu: mu.sqrt(),
            r0,
            v0,
            r0n,
            c1: dot(&r0, &v0) / mu.sqrt(),
            c2: 1.0 - alpha * r0n,
            alpha,
            period: period.filter(|t| t.is_finite()),
            r_periapsis: p / (1.0 + ecc),
            ecc,
        })
    }

    /// An orbiter on the elliptic orbit `elements` (seed 003 Table 3 gives one).
    ///
    /// Errors: non-finite values, `a ≤ 0`, `e ∉ [0, 1)`, or an initial radius ≤ planet radius.
    /// Angles may take any finite value.
    pub fn from_elements(planet: &Planet, elements: &KeplerElements) -> Result<Self, BeaconError> {
        check_planet(planet)?;
        let el = elements;
        check_finite("orbit semi-major axis a [m]", el.a)?;
        check_finite("orbit eccentricity e", el.e)?;
        check_finite("orbit inclination [rad]", el.inc)?;
        check_finite("orbit RAAN [rad]", el.raan)?;
        check_finite("orbit argument of periapsis [rad]", el.argp)?;
        check_finite("orbit true anomaly [rad]", el.true_anomaly)?;
        if el.a <= 0.0 {
            return Err(BeaconError::invalid(
                "orbit semi-major axis a [m]",
                el.a,
                "> 0",
            ));
        }
        if !(0.0..1.0).contains(&el.e) {
            return Err(BeaconError::invalid("orbit eccentricity e", el.e, "[0, 1)"));
        }
        let (r0, v0) = el.to_state(planet.mu);
        Self::from_state(planet, r0, v0)
    }

    /// An orbiter on the circular orbit of seed 002 eq. 55–56.
    ///
    /// Errors: non-finite values or `altitude ≤ 0`.
    pub fn from_circular(planet: &Planet, orbit: &CircularOrbit) -> Result<Self, BeaconError> {
        check_planet(planet)?;
        check_finite("circular orbit altitude [m]", orbit.altitude)?;
        check_finite("circular orbit RAAN [rad]", orbit.raan)?;
        check_finite("circular orbit inclination [rad]", orbit.inc)?;
        check_finite("circular orbit true anomaly [rad]", orbit.true_anomaly)?;
        if orbit.altitude <= 0.0 {
            return Err(BeaconError::invalid(
                "circular orbit altitude [m]",
                orbit.altitude,
                "> 0",
            ));
        }
        let (r0, v0) = orbit.to_state(planet);
        Self::from_state(planet, r0, v0)
    }

    /// Gravitational parameter μ [m³/s²].
    pub fn mu(&self) -> f64 {
        self.mu
    }

    /// Inertial position \[m\] and velocity [m/s] at t = 0.
    pub fn initial_state(&self) -> ([f64; 3], [f64; 3]) {
        (self.r0, self.v0)
    }

    /// Specific orbital energy `v²/2 − μ/r` [m²/s²] (constant of the motion).
    pub fn specific_energy(&self) -> f64 {
        -0.5 * self.mu * self.alpha
    }

    /// Specific angular momentum `r × v` [m²/s] (constant of the motion).
    pub fn angular_momentum(&self) -> [f64; 3] {
        cross(&self.r0, &self.v0)
    }

    /// Semi-major axis `1/α` \[m\]: positive for ellipses, negative for hyperbolas, ∞ for parabolas.
    pub fn semi_major_axis(&self) -> f64 {
        1.0 / self.alpha
    }

    /// Eccentricity.
    pub fn eccentricity(&self) -> f64 {
        self.ecc
    }

    /// Periapsis radius \[m\].
    pub fn periapsis_radius(&self) -> f64 {
        self.r_periapsis
    }

    /// Orbital period \[s\] for elliptic orbits, `None` otherwise.
    pub fn period(&self) -> Option<f64> {
        self.period
    }

    /// Residual of the universal Kepler equation and its derivative (= the radius) at `chi`:
    /// `F(χ) = c1 χ² C + (1 − α r0) χ³ S + r0 χ − √μ Δt`.
    #[inline]
    fn kepler(&self, chi: f64, target: f64) -> (f64, f64) {
        let chi2 = chi * chi;
        let z = self.alpha * chi2;
        let (c, s) = stumpff(z);
        let f = self.c1 * chi2 * c + self.c2 * chi2 * chi * s + self.r0n * chi - target;
        let df = self.c1 * chi * (1.0 - z * s) + self.c2 * chi2 * c + self.r0n;
        (f, df)
    }

    /// Solve the universal Kepler equation for `dt` (already reduced to one period if elliptic).
    fn solve_chi(&self, dt: f64) -> f64 {
        let target = self.sqrt_mu * dt;
        // F' = r ≥ r_p, so |χ| ≤ √μ|Δt|/r_p; for |Δt| ≤ T/2, |ΔE| ≤ π + 2e < 2π and χ = √a ΔE.
        let mut bound = target.abs() / self.r_periapsis;
        if self.period.is_some() {
            bound = bound.min(TAU / self.alpha.sqrt());
        }
        bound = bound * (1.0 + 1e-9) + f64::MIN_POSITIVE;
        let (mut lo, mut hi) = if dt > 0.0 {
            (0.0, bound)
        } else {
            (-bound, 0.0)
        };
        let mut x = self.initial_guess(dt);
        if !(x > lo && x < hi) {
            x = 0.5 * (lo + hi);
        }
        // Safeguarded Newton ("rtsafe"): bisect when the Newton step leaves the bracket or does
        // not shrink at least twice as fast as two steps ago (Newton crawls on the exponential
        // flank of hyperbolic orbits).
        let (mut step, mut step_old) = (hi - lo, hi - lo);
        for _ in 0..300 {
            let (f, df) = self.kepler(x, target);
            if f == 0.0 {
                return x;
            }
            // F is increasing. Stumpff overflow (F = ±∞ or NaN) only happens for |χ| far beyond
            // the root, on the side of x's sign, because |z| grows with |χ|.
            let beyond = if f.is_finite() { f > 0.0 } else { x > 0.0 };
            if beyond {
                hi = x;
            } else {
                lo = x;
            }
            let newton = x - f / df;
            let fast = (2.0 * f).abs() <= (step_old * df).abs();
            let next = if newton > lo && newton < hi && fast {
                newton
            } else {
                0.5 * (lo + hi)
            };
            step_old = step;
            step = next - x;
            if step.abs() <= 2.0 * f64::EPSILON * next.abs()
                || hi - lo <= f64::EPSILON * hi.abs().max(lo.abs())
            {
                return next;
            }
            x = next;
        }
        x
    }

    /// Starting guess for χ (Vallado, Algorithm 8).
    fn initial_guess(&self, dt: f64) -> f64 {
        if self.alpha > 1e-12 / self.r0n {
            return self.sqrt_mu * dt * self.alpha;
        }
        if self.alpha < -1e-12 / self.r0n {
            let a = 1.0 / self.alpha;
            let sign = dt.signum();
            let rv = self.c1 * self.sqrt_mu;
            let denom = rv + sign * (-self.mu * a).sqrt() * (1.0 - self.r0n * self.alpha);
            let guess = sign * (-a).sqrt() * ((-2.0 * self.mu * self.alpha * dt) / denom).ln();
            if guess.is_finite() {
                return guess;
            }
        }
        self.sqrt_mu * dt / self.r0n
    }
}

impl BeaconMotion for Orbiter {
    /// Exact two-body state at `t` \[s\] (seed 003 eq. 8) from the Lagrange coefficients
    /// `f = 1 − χ²C/r0`, `g = (r0·v0/μ) χ² C + r0 χ (1 − zS)/√μ`, `ḟ = √μ χ (zS − 1)/(r r0)`,
    /// `ġ = 1 − χ²C/r`. All four are functions of χ only, so the returned state lies on the conic
    /// to rounding even if the time solve is imperfect. Elliptic times are first reduced to
    /// `[−T/2, T/2]`. A non-finite `t` returns NaN vectors.
    fn state_at(&self, t: f64) -> ([f64; 3], [f64; 3]) {
        if !t.is_finite() {
            return ([f64::NAN; 3], [f64::NAN; 3]);
        }
        let dt = match self.period {
            Some(period) => t - period * (t / period).round(),
            None => t,
        };
        if dt == 0.0 {
            return (self.r0, self.v0);
        }
        let chi = self.solve_chi(dt);
        let chi2 = chi * chi;
        let z = self.alpha * chi2;
        let (c, s) = stumpff(z);
        let f = 1.0 - chi2 * c / self.r0n;
        let g = (self.c1 * chi2 * c + self.r0n * chi * (1.0 - z * s)) / self.sqrt_mu;
        let r = add(&scale(f, &self.r0), &scale(g, &self.v0));
        let rn = norm(&r);
        let fdot = self.sqrt_mu * chi * (z * s - 1.0) / (rn * self.r0n);
        let gdot = 1.0 - chi2 * c / rn;
        let v = add(&scale(fdot, &self.r0), &scale(gdot, &self.v0));
        (r, v)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quarter_period_of_circular_orbit() {
        let mars = Planet::MARS;
        let orb = Orbiter::from_circular(
            &mars,
            &CircularOrbit {
                altitude: 400e3,
                raan: 0.0,
                inc: 0.0,
                true_anomaly: 0.0,
            },
        )
        .unwrap();
        let t = orb.period().unwrap() / 4.0;
        let (r, v) = orb.state_at(t);
        let a = mars.radius + 400e3;
        assert!(r[0].abs() < 1e-6 && (r[1] - a).abs() < 1e-6, "{r:?}");
        assert!((v[0] + (mars.mu / a).sqrt()).abs() < 1e-9);
    }

    #[test]
    fn rejects_bad_states() {
        let mars = Planet::MARS;
        let below = Orbiter::from_state(&mars, [3.0e6, 0.0, 0.0], [0.0, 3e3, 0.0]);
        assert!(matches!(below, Err(BeaconError::Invalid { .. })));
        assert!(Orbiter::from_state(&mars, [4.0e6, 0.0, 0.0], [1e3, 0.0, 0.0]).is_err());
        assert!(Orbiter::from_state(&mars, [4.0e6, 0.0, 0.0], [0.0; 3]).is_err());
        assert!(Orbiter::from_state(&mars, [4.0e6, f64::NAN, 0.0], [0.0, 3e3, 0.0]).is_err());
        let el = KeplerElements {
            a: 4e6,
            e: 1.0,
            inc: 0.0,
            raan: 0.0,
            argp: 0.0,
            true_anomaly: 0.0,
        };
        assert!(Orbiter::from_elements(&mars, &el).is_err());
        let c = CircularOrbit {
            altitude: -1.0,
            raan: 0.0,
            inc: 0.0,
            true_anomaly: 0.0,
        };
        let err = Orbiter::from_circular(&mars, &c).unwrap_err().to_string();
        assert!(err.contains("altitude") && err.contains("> 0"), "{err}");
    }

    #[test]
    fn non_finite_time_gives_nan_not_panic() {
        let mars = Planet::MARS;
        let orb = Orbiter::from_state(&mars, [4.0e6, 0.0, 0.0], [0.0, 3.3e3, 0.0]).unwrap();
        assert!(orb.state_at(f64::NAN).0[0].is_nan());
        assert!(orb.state_at(f64::INFINITY).1[0].is_nan());
    }
}
