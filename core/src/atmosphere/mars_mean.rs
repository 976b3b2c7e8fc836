//! Built-in non-exponential mean Mars density profile (0-150 km).
//!
//! We cannot ship seed 001's Mars-GRAM profiles (docs/references.md), so its truth atmosphere is
//! a non-exponential mean profile plus altitude-correlated random perturbations. This file
//! defines that mean profile. It is **our own synthetic profile**, not a
//! Mars-GRAM, MCD or COSPAR product; it is only meant to be physically plausible:
//!
//! * Temperature T(h) is a piecewise-linear profile through [`MARS_MEAN_TEMPERATURE_KNOTS`] whose
//!   corners are rounded with a softplus of width [`MARS_MEAN_KNEE_WIDTH_M`] (so T, and hence the
//!   log-density slope, are smooth). Shape: a weak lapse rate in the lower atmosphere
//!   (195 K at the surface), a nearly isothermal 165 K layer around 40-60 km, a mesopause
//!   (≈ 133 K near 110 km) and a warming thermosphere (200 K at 150 km) — the qualitative
//!   structure of Viking-era and climate-database mean profiles, with values chosen by us.
//! * Pressure follows hydrostatic equilibrium d ln p/dh = −g(h)/(R_s·T(h)) from
//!   p(0) = [`MARS_MEAN_SURFACE_PRESSURE_PA`], with g(h) = μ/(R + h)² (the Mars constants of [`crate::planet`])
//!   and R_s = R_u / 43.34 g/mol (CO₂-dominated air, [`MARS_MEAN_GAS_CONSTANT`]). The integral is
//!   done with composite Simpson's rule, 20 sub-steps per km.
//! * ρ = p/(R_s·T) on a 1 km grid from 0 to 150 km, interpolated by [`Tabulated`].
//!
//! Resulting values (kg/m³): 0 km 1.55e-2, 20 km 2.14e-3, 40 km 2.44e-4, 41 km 2.18e-4
//! (the seed-000 exponential gives 2.0e-4 there), 60 km 2.57e-5, 80 km 2.67e-6,
//! 100 km 2.45e-7, 120 km 1.63e-8, 150 km 4.5e-10. The local density scale height
//! −1/(d ln ρ/dh) falls from 10.7 km at the surface to 8.9 km at 40-70 km and 7.3 km at
//! 110-120 km, then rises again to 10 km at 150 km, so the profile is clearly not exponential.

use std::sync::OnceLock;

use super::tabulated::Tabulated;
use crate::planet::Planet;

/// Temperature corners of the built-in profile: (altitude (m), temperature (K)).
pub const MARS_MEAN_TEMPERATURE_KNOTS: [(f64, f64); 10] = [
    (0.0, 195.0),
    (10_000.0, 184.0),
    (20_000.0, 175.0),
    (40_000.0, 166.0),
    (60_000.0, 165.0),
    (80_000.0, 157.0),
    (100_000.0, 136.0),
    (112_000.0, 128.0),
    (125_000.0, 145.0),
    (150_000.0, 200.0),
];

/// Width over which the corners of the temperature profile are rounded (m).
pub const MARS_MEAN_KNEE_WIDTH_M: f64 = 4_000.0;

/// Surface (h = 0) pressure of the built-in profile (Pa).
pub const MARS_MEAN_SURFACE_PRESSURE_PA: f64 = 580.0;

/// Specific gas constant of the built-in profile: 8.314462618 / 0.04334 (J/(kg·K)).
pub const MARS_MEAN_GAS_CONSTANT: f64 = 8.314_462_618 / 0.043_34;

/// Top of the built-in profile (m); knots every 1 km from 0.
pub const MARS_MEAN_TOP_M: f64 = 150_000.0;

/// `w·ln(1 + exp(x/w))`, evaluated without overflow.
fn softplus(x: f64, w: f64) -> f64 {
    let u = x / w;
    if u > 0.0 {
        x + w * (-u).exp().ln_1p()
    } else {
        w * u.exp().ln_1p()
    }
}

/// Temperature (K) of the built-in profile at altitude `h_m` (m) (smoothed piecewise-linear,
/// extended linearly beyond the end knots).
pub fn mars_mean_temperature(h_m: f64) -> f64 {
    let k = &MARS_MEAN_TEMPERATURE_KNOTS;
    let slope = |i: usize| (k[i + 1].1 - k[i].1) / (k[i + 1].0 - k[i].0);
    let mut t = k[0].1 + slope(0) * (h_m - k[0].0);
    for (i, knot) in k.iter().enumerate().take(k.len() - 1).skip(1) {
        t += (slope(i) - slope(i - 1)) * softplus(h_m - knot.0, MARS_MEAN_KNEE_WIDTH_M);
    }
    t
}

fn build() -> Tabulated {
    let mars = Planet::MARS;
    let dlnp = |h: f64| {
        let r = mars.radius + h;
        -(mars.mu / (r * r)) / (MARS_MEAN_GAS_CONSTANT * mars_mean_temperature(h))
    };
    let steps_per_km = 20;
    let dh = 1_000.0 / steps_per_km as f64;
    let n = (MARS_MEAN_TOP_M / 1_000.0).round() as usize + 1;
    let mut alt = Vec::with_capacity(n);
    let mut ln_rho = Vec::with_capacity(n);
    let mut ln_p = MARS_MEAN_SURFACE_PRESSURE_PA.ln();
    for k in 0..n {
        let h = k as f64 * 1_000.0;
        alt.push(h);
        ln_rho.push(ln_p - (MARS_MEAN_GAS_CONSTANT * mars_mean_temperature(h)).ln());
        for j in 0..steps_per_km {
            let a = h + j as f64 * dh;
            ln_p += dh / 6.0 * (dlnp(a) + 4.0 * dlnp(a + 0.5 * dh) + dlnp(a + dh));
        }
    }
    Tabulated::from_log_knots(alt, ln_rho)
}

/// The built-in mean Mars profile (`model = "mars-mean"`), 151 knots from 0 to 150 km: a
/// hydrostatic integration of our smoothed piecewise-linear temperature profile, see
/// [the module documentation](self) for the construction and values. Computed once and cached.
pub fn mars_mean_profile() -> Tabulated {
    static PROFILE: OnceLock<Tabulated> = OnceLock::new();
    PROFILE.get_or_init(build).clone()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::atmosphere::Atmosphere;

    #[test]
    fn values_are_plausible_and_not_exponential() {
        let p = mars_mean_profile();
        assert_eq!(p.num_knots(), 151);
        assert_eq!(p.altitude_range(), (0.0, 150_000.0));
        for h in [0, 20, 40, 41, 60, 80, 100, 120, 150] {
            println!("{h:4} km  {:.4e}", p.density(h as f64 * 1e3));
        }
        let rho0 = p.density(0.0);
        assert!((0.015..0.020).contains(&rho0), "{rho0}");
        let r41 = p.density(41e3);
        assert!((1.5e-4..3.0e-4).contains(&r41), "{r41}");
        let r80 = p.density(80e3);
        assert!((1.5e-6..5e-6).contains(&r80), "{r80}");
        // Local density scale height −1/(d ln ρ/dh) must vary by > 20 %.
        let hs = |h: f64| {
            let d = p.log_density(h + 500.0) - p.log_density(h - 500.0);
            -1000.0 / d
        };
        let (lo, hi) = (hs(100e3), hs(5e3));
        println!("scale height 5 km: {hi:.0} m, 100 km: {lo:.0} m");
        assert!(hi / lo > 1.2, "{hi} {lo}");
        // Monotonically decreasing density.
        let k = p.knot_densities();
        assert!(k.windows(2).all(|w| w[1] < w[0]));
    }

    #[test]
    fn temperature_passes_near_knots() {
        for &(h, t) in &MARS_MEAN_TEMPERATURE_KNOTS[1..9] {
            assert!((mars_mean_temperature(h) - t).abs() < 6.0, "{h} {t}");
        }
        assert!((mars_mean_temperature(0.0) - 195.0).abs() < 0.5);
    }
}
