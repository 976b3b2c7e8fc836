//! What a density perturbation is drawn from ([`PerturbationSpec`]): the 1σ envelope σ(h) of
//! ρ/ρ_mean − 1 ([`Envelope`]), the correlation length of z(h), its AR(1) grid and the scale. The
//! realisation is [`Perturbed`](super::model::Perturbed).

use super::error::{AtmosphereError, check_closed, check_open};
use crate::math::Real;

/// Piecewise-linear 1σ relative-density envelope σ(h), constant beyond its end points.
#[derive(Debug, Clone, PartialEq)]
pub struct Envelope {
    /// (altitude (m), σ as a fraction of the mean), strictly increasing in altitude.
    points: Vec<(f64, f64)>,
}

impl Envelope {
    /// Build from `(altitude_m, sigma_fraction)` points: at least one, finite, altitudes strictly
    /// increasing, σ in [0, 10]. Errors name the 1-based point.
    pub fn new(points: Vec<(f64, f64)>) -> Result<Envelope, AtmosphereError> {
        if points.is_empty() {
            return Err(AtmosphereError::InvalidField {
                field: "envelope".to_string(),
                problem: "needs at least one (altitude, sigma) point".to_string(),
            });
        }
        for (i, &(h, s)) in points.iter().enumerate() {
            check_open(&format!("envelope[{i}].altitude_m"), h, -1e8, 1e8)?;
            check_closed(&format!("envelope[{i}].sigma"), s, 0.0, 10.0)?;
            if i > 0 && h <= points[i - 1].0 {
                return Err(AtmosphereError::InvalidField {
                    field: format!("envelope[{i}]"),
                    problem: format!(
                        "altitude {h} m does not increase (previous point is at {} m)",
                        points[i - 1].0
                    ),
                });
            }
        }
        Ok(Envelope { points })
    }

    /// Points taken as they are, for [`super::config::PerturbationConfig::to_spec`] (validated elsewhere).
    pub(super) fn from_points_unchecked(points: Vec<(f64, f64)>) -> Envelope {
        Envelope { points }
    }

    /// The `(altitude_m, sigma)` points.
    pub fn points(&self) -> &[(f64, f64)] {
        &self.points
    }

    /// σ(h) by linear interpolation, generic so that dσ/dh flows into derivatives.
    pub fn sigma<T: Real>(&self, altitude_m: T) -> T {
        let p = &self.points;
        let x = altitude_m.re();
        let n = p.len();
        if n == 0 {
            return T::from(0.0);
        }
        if x.is_nan() || x <= p[0].0 {
            return T::from(p[0].1);
        }
        if x >= p[n - 1].0 {
            return T::from(p[n - 1].1);
        }
        // The clamp only matters for unvalidated (unsorted) points; it keeps indexing in bounds.
        let i = p.partition_point(|q| q.0 <= x).clamp(1, n - 1) - 1;
        let w = (altitude_m - p[i].0) / (p[i + 1].0 - p[i].0);
        w * (p[i + 1].1 - p[i].1) + p[i].1
    }
}

impl Default for Envelope {
    /// Our envelope (docs/density.md, docs/references.md): 0 km 2 %, 40 km 5 %, 60 km 8.5 %, 80 km 17.5 %, 100-150 km 30 %.
    fn default() -> Self {
        Envelope {
            points: vec![
                (0.0, 0.02),
                (40e3, 0.05),
                (60e3, 0.085),
                (80e3, 0.175),
                (100e3, 0.30),
                (120e3, 0.30),
                (150e3, 0.30),
            ],
        }
    }
}

/// Parameters of the perturbation process.
#[derive(Debug, Clone, PartialEq)]
pub struct PerturbationSpec {
    /// 1σ envelope of ρ/ρ_mean − 1 (before `scale`).
    pub envelope: Envelope,
    /// Correlation length L of z(h) (m) (default 8 km).
    pub correlation_length_m: f64,
    /// Spacing of the AR(1) grid (m) (default 1 km).
    pub grid_step_m: f64,
    /// Lowest grid altitude (m) (default 0).
    pub grid_bottom_m: f64,
    /// Highest altitude the grid must reach (m) (default 150 km).
    pub grid_top_m: f64,
    /// Multiplier of the envelope: σ_used = scale·σ(h); 0 gives exactly the mean profile.
    pub scale: f64,
}

impl Default for PerturbationSpec {
    fn default() -> Self {
        PerturbationSpec {
            envelope: Envelope::default(),
            correlation_length_m: 8_000.0,
            grid_step_m: 1_000.0,
            grid_bottom_m: 0.0,
            grid_top_m: 150_000.0,
            scale: 1.0,
        }
    }
}

impl PerturbationSpec {
    /// Check ranges: L in (0, 1e7) m, step in (0, grid height], at most 1e6 grid points,
    /// bottom < top (both finite), scale in [0, 10].
    pub fn validate(&self) -> Result<(), AtmosphereError> {
        check_open("correlation_length_m", self.correlation_length_m, 0.0, 1e7)?;
        check_open("grid_bottom_m", self.grid_bottom_m, -1e8, 1e8)?;
        check_open("grid_top_m", self.grid_top_m, self.grid_bottom_m, 1e8)?;
        let span = self.grid_top_m - self.grid_bottom_m;
        check_closed("grid_step_m", self.grid_step_m, span / 1e6, span)?;
        check_closed("scale", self.scale, 0.0, 10.0)?;
        Ok(())
    }

    /// Number of AR(1) grid points (and of standard normals a realisation takes).
    pub fn grid_len(&self) -> usize {
        ((self.grid_top_m - self.grid_bottom_m) / self.grid_step_m - 1e-9).ceil() as usize + 1
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn envelope_interpolates_and_clamps() {
        let e = Envelope::default();
        assert!((e.sigma(20e3_f64) - 0.035).abs() < 1e-15);
        assert!((e.sigma(-5e3_f64) - 0.02).abs() < 1e-15);
        assert!((e.sigma(200e3_f64) - 0.30).abs() < 1e-15);
        assert!(Envelope::new(vec![]).is_err());
        assert!(Envelope::new(vec![(0.0, 0.1), (0.0, 0.2)]).is_err());
        assert!(Envelope::new(vec![(0.0, -0.1)]).is_err());
    }

    #[test]
    fn spec_validation() {
        assert!(PerturbationSpec::default().validate().is_ok());
        let bad = PerturbationSpec {
            correlation_length_m: 0.0,
            ..Default::default()
        };
        assert!(bad.validate().is_err());
        let bad = PerturbationSpec {
            grid_step_m: 0.0,
            ..Default::default()
        };
        assert!(bad.validate().is_err());
        let bad = PerturbationSpec {
            scale: f64::NAN,
            ..Default::default()
        };
        assert!(bad.validate().is_err());
        assert_eq!(PerturbationSpec::default().grid_len(), 151);
    }
}
