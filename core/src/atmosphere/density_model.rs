//! [`Atmosphere`]: the trait every density model implements, ρ(h) generic over [`Real`] so that
//! Jacobians can be taken through it by forward-mode AD.

use crate::math::Real;

/// A density model ρ(h).
pub trait Atmosphere {
    /// Density (kg/m³) at altitude `altitude_m` (m) above the reference sphere.
    fn density<T: Real>(&self, altitude_m: T) -> T;
}
