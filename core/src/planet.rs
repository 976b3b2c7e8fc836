//! Planet constants (the Mars values common to the four papers, docs/references.md), overridable per scenario.

use serde::{Deserialize, Serialize};

/// Gravitational and geometric constants of the central body.
///
/// Defaults are Mars as we settled it for all four papers: μ = 4.2828e13 m³/s², mean radius 3396.2 km,
/// rotation rate 7.0882e-5 rad/s. Seed 000 uses μ = 4.282829e13; a scenario may override any value.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Planet {
    /// Gravitational parameter μ [m³/s²].
    pub mu: f64,
    /// Mean (reference-sphere) radius R \[m\]; altitude is `r − R`.
    pub radius: f64,
    /// Rotation rate ω about the +z axis [rad/s].
    pub rotation_rate: f64,
}

impl Planet {
    /// Mars with the default constants above.
    pub const MARS: Planet = Planet {
        mu: 4.2828e13,
        radius: 3_396_200.0,
        rotation_rate: 7.0882e-5,
    };

    /// Surface gravity g0 = μ/R² [m/s²].
    pub fn surface_gravity(&self) -> f64 {
        self.mu / (self.radius * self.radius)
    }
}

impl Default for Planet {
    fn default() -> Self {
        Planet::MARS
    }
}

/// Standard Earth gravity used to convert accelerometer specifications in µg [m/s²].
pub const G_EARTH: f64 = 9.80665;

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mars_surface_gravity_is_about_3_71() {
        let g = Planet::MARS.surface_gravity();
        assert!((g - 3.713).abs() < 0.01, "g0 = {g}");
    }
}
