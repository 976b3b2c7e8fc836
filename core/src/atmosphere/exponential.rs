//! Isothermal exponential density model and its least-squares fit.

use super::density_model::Atmosphere;
use super::error::{AtmosphereError, check_open};
use crate::math::Real;

/// Exponential (isothermal) density model ρ(h) = ρ_ref·exp(−(h − h_ref)/H).
///
/// This is seed 000 eq. 3 and seed 001 eq. 16, written in altitude h = r − R instead of
/// radius: `(r0 − r)/hs = −(h − h_ref)/H` with `h_ref = r0 − R`. Seeds 000, 002 and 003 use
/// ρ0 = 2e-4 kg/m³, r0 = 3437.2 km, hs = 7.5 km (see [`Exponential::mars_reference`]).
///
/// Fields are SI: kg/m³ and metres. [`Exponential::new`] and
/// [`Exponential::from_reference_radius`] check them; a value built with a struct literal can be
/// checked with [`Exponential::validate`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Exponential {
    /// Density at the reference altitude (kg/m³).
    pub rho_ref: f64,
    /// Reference altitude above the reference sphere (m).
    pub h_ref: f64,
    /// Density scale height H (m).
    pub scale_height: f64,
}

/// Exponential density with every parameter a [`Real`], for filters that estimate ρ_ref or H as
/// states (seed 000 augments ρ0; seed 001 eq. 24-25 corrects the nominal profile).
///
/// Returns `rho_ref·exp(−(altitude − h_ref)/scale_height)` (seed 001 eq. 16).
#[inline]
pub fn exponential_density<T: Real>(rho_ref: T, h_ref: T, scale_height: T, altitude_m: T) -> T {
    rho_ref * (-(altitude_m - h_ref) / scale_height).exp()
}

impl Exponential {
    /// Build from reference density, reference altitude and scale height (SI), checking that the
    /// density is in (0, 1e3) kg/m³, the scale height in (0, 1e7) m and the altitude finite.
    pub fn new(rho_ref: f64, h_ref: f64, scale_height: f64) -> Result<Self, AtmosphereError> {
        let e = Exponential {
            rho_ref,
            h_ref,
            scale_height,
        };
        e.validate()?;
        Ok(e)
    }

    /// Build from the papers' radius form ρ = ρ0·exp((r0 − r)/hs) (seed 000 eq. 3, seed 001 eq. 16):
    /// `h_ref = r_ref_m − planet_radius_m`.
    pub fn from_reference_radius(
        rho_ref: f64,
        r_ref_m: f64,
        scale_height_m: f64,
        planet_radius_m: f64,
    ) -> Result<Self, AtmosphereError> {
        check_open("planet_radius_m", planet_radius_m, 0.0, f64::INFINITY)?;
        check_open("r_ref_m", r_ref_m, 0.0, f64::INFINITY)?;
        Self::new(rho_ref, r_ref_m - planet_radius_m, scale_height_m)
    }

    /// The model of seeds 000/002/003: ρ0 = 2e-4 kg/m³ at r0 = 3437.2 km, hs = 7.5 km,
    /// expressed over a sphere of radius `planet_radius_m` (3396.2 km gives h_ref = 41 km).
    pub fn mars_reference(planet_radius_m: f64) -> Self {
        Exponential {
            rho_ref: 2.0e-4,
            h_ref: 3_437_200.0 - planet_radius_m,
            scale_height: 7_500.0,
        }
    }

    /// Check the parameters (finite, ρ_ref in (0, 1e3) kg/m³, H in (0, 1e7) m).
    pub fn validate(&self) -> Result<(), AtmosphereError> {
        check_open("rho_ref", self.rho_ref, 0.0, 1e3)?;
        check_open("scale_height", self.scale_height, 0.0, 1e7)?;
        check_open("h_ref", self.h_ref, -1e8, 1e8)?;
        Ok(())
    }

    /// Least-squares fit of ln ρ = a + b·h to `(altitude_m, density)` samples, returned as an
    /// exponential with `h_ref` at the mean sample altitude, `rho_ref = exp(a + b·h_ref)` and
    /// `H = −1/b`.
    ///
    /// This is how seed 001 §IV.A builds its onboard model ("a least-squares exponential fit ...
    /// from multiple realizations of Mars-GRAM profiles"): pass the samples of one or many
    /// profiles. The fit is unweighted in ln ρ, i.e. it minimises relative density errors.
    ///
    /// Errors: fewer than 2 samples, a non-finite value, a non-positive density, all altitudes
    /// equal, or a fitted density that does not decrease with altitude.
    pub fn fit_least_squares(samples: &[(f64, f64)]) -> Result<Exponential, AtmosphereError> {
        if samples.len() < 2 {
            return Err(AtmosphereError::FitFailed {
                problem: format!("need at least 2 samples, got {}", samples.len()),
            });
        }
        for (i, &(h, rho)) in samples.iter().enumerate() {
            if !h.is_finite() || !rho.is_finite() || rho <= 0.0 {
                return Err(AtmosphereError::FitFailed {
                    problem: format!(
                        "sample {} (altitude {h} m, density {rho} kg/m³) must be finite with positive density",
                        i + 1
                    ),
                });
            }
        }
        let n = samples.len() as f64;
        let h_mean = samples.iter().map(|s| s.0).sum::<f64>() / n;
        let y_mean = samples.iter().map(|s| s.1.ln()).sum::<f64>() / n;
        // Centred sums keep the normal equations well conditioned.
        let (mut sxx, mut sxy) = (0.0, 0.0);
        for &(h, rho) in samples {
            let dx = h - h_mean;
            sxx += dx * dx;
            sxy += dx * (rho.ln() - y_mean);
        }
        let spread = samples
            .iter()
            .map(|s| (s.0 - h_mean).abs())
            .fold(0.0_f64, f64::max);
        if sxx <= 0.0 || spread <= 1e-9 * h_mean.abs().max(1.0) {
            return Err(AtmosphereError::FitFailed {
                problem: "all sample altitudes are equal".to_string(),
            });
        }
        let slope = sxy / sxx;
        if slope.is_nan() || slope >= 0.0 {
            return Err(AtmosphereError::FitFailed {
                problem: format!(
                    "fitted log-density slope {slope} 1/m is not negative (density does not decrease with altitude)"
                ),
            });
        }
        Exponential::new(y_mean.exp(), h_mean, -1.0 / slope)
    }

    /// The same model with its reference moved to `h_ref_new` (density rescaled accordingly).
    pub fn with_reference_altitude(&self, h_ref_new: f64) -> Exponential {
        Exponential {
            rho_ref: self.rho_ref * (-(h_ref_new - self.h_ref) / self.scale_height).exp(),
            h_ref: h_ref_new,
            scale_height: self.scale_height,
        }
    }
}

impl Atmosphere for Exponential {
    /// Seed 001 eq. 16 / seed 000 eq. 3.
    fn density<T: Real>(&self, altitude_m: T) -> T {
        ((altitude_m - self.h_ref) * (-1.0 / self.scale_height)).exp() * self.rho_ref
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn fit_rejects_degenerate_input() {
        assert!(Exponential::fit_least_squares(&[(0.0, 1.0)]).is_err());
        assert!(Exponential::fit_least_squares(&[(5.0, 1.0), (5.0, 2.0)]).is_err());
        assert!(Exponential::fit_least_squares(&[(0.0, 1.0), (1.0, -2.0)]).is_err());
        assert!(Exponential::fit_least_squares(&[(0.0, 1.0), (1.0, 2.0)]).is_err());
        assert!(Exponential::fit_least_squares(&[(0.0, f64::NAN), (1.0, 2.0)]).is_err());
    }

    #[test]
    fn generic_form_matches_model() {
        let e = Exponential::mars_reference(3_396_200.0);
        let h = 55_000.0;
        let g = exponential_density(e.rho_ref, e.h_ref, e.scale_height, h);
        assert!((g / e.density(h) - 1.0).abs() < 1e-14);
    }

    #[test]
    fn moving_reference_keeps_profile() {
        let e = Exponential::mars_reference(3_396_200.0);
        let m = e.with_reference_altitude(0.0);
        for h in [0.0_f64, 30e3, 90e3] {
            assert!((m.density(h) / e.density(h) - 1.0).abs() < 1e-12);
        }
    }

    #[test]
    fn new_rejects_bad_parameters() {
        assert!(Exponential::new(-1.0, 0.0, 7500.0).is_err());
        assert!(Exponential::new(1e-4, 0.0, 0.0).is_err());
        assert!(Exponential::new(1e-4, f64::NAN, 7500.0).is_err());
        let msg = Exponential::new(1e-4, 0.0, -3.0).unwrap_err().to_string();
        assert!(msg.contains("scale_height = -3"), "{msg}");
    }
}
