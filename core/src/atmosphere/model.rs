//! Closed set of density models behind one enum, for scenario-driven code, and the perturbed
//! model ([`Perturbed`]), a mean model of that set times a random factor: the two types contain
//! each other, so they live in one file.
//!
//! # The perturbed-profile generator
//!
//! A mean model × a positive, mean-one, altitude-correlated factor.
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

use super::cospar::Cospar;
use super::density_model::Atmosphere;
use super::error::AtmosphereError;
use super::exponential::Exponential;
use super::perturbation_spec::PerturbationSpec;
use super::tabulated::Tabulated;
use crate::math::Real;

/// Any atmosphere the crate provides, dispatched by `match` (no trait objects, so the generic
/// [`Atmosphere::density`] stays usable with dual numbers).
#[derive(Debug, Clone, PartialEq)]
pub enum AtmosphereModel {
    /// Exponential model, seed 000 eq. 3 / seed 001 eq. 16.
    Exponential(Exponential),
    /// Simplified COSPAR model, seed 001 eq. 17.
    Cospar(Cospar),
    /// ln ρ cubic-spline table (seed 001 §V), e.g. parsed Mars-GRAM output or the built-in mean.
    Tabulated(Tabulated),
    /// A mean model times a random altitude-correlated factor (docs/density.md).
    Perturbed(Box<Perturbed>),
}

impl AtmosphereModel {
    /// Altitude interval (m) outside which the model extrapolates, or `None` if it is defined
    /// everywhere (analytic models). For a perturbed model this is the mean model's interval.
    pub fn valid_altitude_range(&self) -> Option<(f64, f64)> {
        match self {
            AtmosphereModel::Exponential(_) | AtmosphereModel::Cospar(_) => None,
            AtmosphereModel::Tabulated(t) => Some(t.altitude_range()),
            AtmosphereModel::Perturbed(p) => p.mean().valid_altitude_range(),
        }
    }

    /// Whether `[h_min, h_max]` (m) needs no extrapolation (always true for analytic models).
    pub fn covers(&self, h_min: f64, h_max: f64) -> bool {
        match self.valid_altitude_range() {
            None => h_min <= h_max,
            Some((lo, hi)) => h_min >= lo && h_max <= hi && h_min <= h_max,
        }
    }

    /// Short model name for reports: `exponential`, `cospar`, `table`, `perturbed`.
    pub fn kind(&self) -> &'static str {
        match self {
            AtmosphereModel::Exponential(_) => "exponential",
            AtmosphereModel::Cospar(_) => "cospar",
            AtmosphereModel::Tabulated(_) => "table",
            AtmosphereModel::Perturbed(_) => "perturbed",
        }
    }
}

impl Atmosphere for AtmosphereModel {
    fn density<T: Real>(&self, altitude_m: T) -> T {
        match self {
            AtmosphereModel::Exponential(m) => m.density(altitude_m),
            AtmosphereModel::Cospar(m) => m.density(altitude_m),
            AtmosphereModel::Tabulated(m) => m.density(altitude_m),
            AtmosphereModel::Perturbed(m) => m.density(altitude_m),
        }
    }
}

impl From<Exponential> for AtmosphereModel {
    fn from(m: Exponential) -> Self {
        AtmosphereModel::Exponential(m)
    }
}

impl From<Cospar> for AtmosphereModel {
    fn from(m: Cospar) -> Self {
        AtmosphereModel::Cospar(m)
    }
}

impl From<Tabulated> for AtmosphereModel {
    fn from(m: Tabulated) -> Self {
        AtmosphereModel::Tabulated(m)
    }
}

impl From<Perturbed> for AtmosphereModel {
    fn from(m: Perturbed) -> Self {
        AtmosphereModel::Perturbed(Box::new(m))
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
