//! Perturbed-profile generator: mean model × positive, mean-one, altitude-correlated factor.
//!
//! We replace seed 001's perturbed Mars-GRAM profiles with our own
//! generator: a non-exponential mean profile plus random perturbations whose 1σ grows with
//! altitude (≈ 2 % near the surface, 5 % at 40 km, 8-9 % at 60 km, 15-20 % at 80 km, 25-35 % at
//! 100-120 km). The model here is
//!
//! ρ(h) = ρ_mean(h)·exp(s(h)·z(h) − s(h)²/2),  s(h) = √ln(1 + σ(h)²),
//!
//! a log-normal factor, so ρ/ρ_mean − 1 has mean 0 and standard deviation exactly σ(h) wherever
//! z(h) ~ N(0, 1). z is a stationary Gauss-Markov (first-order, exponentially correlated)
//! process in altitude with correlation exp(−|Δh|/L), drawn on a regular grid by the exact AR(1)
//! recursion z_{k+1} = a·z_k + √(1 − a²)·ε_k, a = exp(−Δ/L), z_0 ~ N(0, 1).
//!
//! Between grid points z is interpolated linearly and divided by the standard deviation of the
//! interpolant, √((1 − w)² + w² + 2w(1 − w)a), so that z(h) has unit variance at every altitude
//! (plain linear interpolation would shrink it by up to 3 % mid-cell for Δ = 1 km, L = 8 km).
//! Outside the grid z is held at its end values. Evaluation is generic over [`Real`].

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

use super::Atmosphere;
use super::error::{AtmosphereError, check_closed, check_open};
use super::model::AtmosphereModel;
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

    /// Points taken as they are, for [`super::PerturbationConfig::to_spec`] (validated elsewhere).
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

/// One random realisation of a perturbed atmosphere; see the module documentation.
#[derive(Debug, Clone, PartialEq)]
pub struct Perturbed {
    mean: AtmosphereModel,
    spec: PerturbationSpec,
    /// Unit-variance AR(1) values at `grid_bottom_m + k·grid_step_m`.
    z: Vec<f64>,
    /// Correlation between neighbouring grid points, exp(−Δ/L).
    a: f64,
}

impl Perturbed {
    /// Draw a realisation from `rng`; the mean model is kept as is.
    ///
    /// `spec` should have passed [`PerturbationSpec::validate`] (scenario validation does this).
    /// This function never panics: for an invalid `spec` it returns the **unperturbed** mean
    /// (scale 0) without drawing. Use [`Perturbed::try_sample`] to get the error instead.
    pub fn sample<R: Rng + ?Sized>(
        mean: AtmosphereModel,
        spec: &PerturbationSpec,
        rng: &mut R,
    ) -> Perturbed {
        if spec.validate().is_err() {
            let spec = PerturbationSpec {
                scale: 0.0,
                ..PerturbationSpec::default()
            };
            let z = vec![0.0; spec.grid_len()];
            let a = (-spec.grid_step_m / spec.correlation_length_m).exp();
            return Perturbed { mean, spec, z, a };
        }
        let normals: Vec<f64> = (0..spec.grid_len())
            .map(|_| StandardNormal.sample(rng))
            .collect();
        Self::from_normals(mean, spec, &normals)
    }

    /// The realisation of the standard normals `normals` (one per grid point, from the bottom;
    /// missing entries are 0): z_0 = n_0, z_k = a·z_{k−1} + √(1 − a²)·n_k, the recursion
    /// [`Perturbed::sample`] applies to its draws. All zero gives z ≡ 0, the median profile
    /// ρ_mean·exp(−s²/2). `spec` should have passed [`PerturbationSpec::validate`].
    pub fn from_normals(
        mean: AtmosphereModel,
        spec: &PerturbationSpec,
        normals: &[f64],
    ) -> Perturbed {
        let n = spec.grid_len();
        let a = (-spec.grid_step_m / spec.correlation_length_m).exp();
        let b = (1.0 - a * a).max(0.0).sqrt();
        let normal = |k: usize| normals.get(k).copied().unwrap_or(0.0);
        let mut z = Vec::with_capacity(n);
        let mut zk = normal(0);
        z.push(zk);
        for k in 1..n {
            zk = a * zk + b * normal(k);
            z.push(zk);
        }
        Perturbed {
            mean,
            spec: spec.clone(),
            z,
            a,
        }
    }

    /// [`Perturbed::sample`] after validating `spec`, returning the validation error if any.
    pub fn try_sample<R: Rng + ?Sized>(
        mean: AtmosphereModel,
        spec: &PerturbationSpec,
        rng: &mut R,
    ) -> Result<Perturbed, AtmosphereError> {
        spec.validate()?;
        Ok(Self::sample(mean, spec, rng))
    }

    /// Reproducible realisation from a seed (ChaCha8 stream seeded with `seed_from_u64`).
    pub fn from_seed(
        mean: AtmosphereModel,
        spec: &PerturbationSpec,
        seed: u64,
    ) -> Result<Perturbed, AtmosphereError> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        Self::try_sample(mean, spec, &mut rng)
    }

    /// The mean model.
    pub fn mean(&self) -> &AtmosphereModel {
        &self.mean
    }

    /// The specification this realisation was drawn with.
    pub fn spec(&self) -> &PerturbationSpec {
        &self.spec
    }

    /// The unit-variance process z at the grid altitudes `grid_bottom_m + k·grid_step_m`.
    pub fn z_grid(&self) -> &[f64] {
        &self.z
    }

    /// z(h): unit-variance, linearly interpolated and renormalised, held constant off the grid.
    pub fn z<T: Real>(&self, altitude_m: T) -> T {
        let n = self.z.len();
        let u = (altitude_m - self.spec.grid_bottom_m) / self.spec.grid_step_m;
        let x = u.re();
        if x.is_nan() || x <= 0.0 {
            return T::from(self.z[0]);
        }
        if x >= (n - 1) as f64 {
            return T::from(self.z[n - 1]);
        }
        let i = (x.floor() as usize).min(n - 2);
        let w = u - i as f64;
        let one_minus_w = -w + 1.0;
        let lin = one_minus_w * self.z[i] + w * self.z[i + 1];
        let var = one_minus_w * one_minus_w + w * w + w * one_minus_w * (2.0 * self.a);
        lin / var.sqrt()
    }

    /// The multiplicative factor ρ/ρ_mean = exp(s·z − s²/2), s = √ln(1 + σ²), σ = scale·σ_env(h).
    pub fn factor<T: Real>(&self, altitude_m: T) -> T {
        let sigma = self.spec.envelope.sigma(altitude_m) * self.spec.scale;
        if sigma.re() <= 0.0 {
            return T::from(1.0);
        }
        let s2 = (sigma * sigma).ln_1p();
        (s2.sqrt() * self.z(altitude_m) - s2 * 0.5).exp()
    }

    /// ρ/ρ_mean − 1 at `altitude_m` (m).
    pub fn relative_deviation(&self, altitude_m: f64) -> f64 {
        self.factor(altitude_m) - 1.0
    }
}

impl Atmosphere for Perturbed {
    fn density<T: Real>(&self, altitude_m: T) -> T {
        self.mean.density(altitude_m) * self.factor(altitude_m)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::atmosphere::Exponential;

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

    #[test]
    fn z_is_continuous_and_interpolates_grid() {
        let mean = AtmosphereModel::Exponential(Exponential::mars_reference(3_396_200.0));
        let p = Perturbed::from_seed(mean, &PerturbationSpec::default(), 7).unwrap();
        for k in [0usize, 10, 75, 150] {
            assert!((p.z(k as f64 * 1e3) - p.z_grid()[k]).abs() < 1e-12);
        }
        let h = 42e3_f64;
        assert!((p.z(h - 1e-6) - p.z(h + 1e-6)).abs() < 1e-6);
        assert_eq!(p.z(-10.0), p.z_grid()[0]);
        assert_eq!(p.z(1e6), p.z_grid()[150]);
    }
}
