//! Closed set of density models behind one enum, for scenario-driven code.

use super::Atmosphere;
use super::cospar::Cospar;
use super::exponential::Exponential;
use super::perturbed::Perturbed;
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
