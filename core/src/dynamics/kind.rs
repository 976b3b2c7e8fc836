//! [`DynamicsKind`]: which equations of motion a model flies, spherical (seed 000 eq. 1,
//! seed 001 eq. 4–6) or Cartesian inertial (seed 003 eq. 1–5).

use serde::Deserialize;
use serde::Serialize;

/// Which equations of motion a model uses.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum DynamicsKind {
    /// Spherical state, non-rotating planet (seed 000 eq. 1 and 7).
    Spherical,
    /// Spherical state relative to a rotating planet (seed 001 eq. 4–6; seed 002 eq. 1).
    SphericalRotating,
    /// Cartesian inertial position/velocity, wind-frame aerodynamics, rotating atmosphere (seed 003 eq. 1–5).
    Cartesian,
}

impl DynamicsKind {
    /// Whether the six kinematic states are `[x, y, z, vx, vy, vz]` (inertial) rather than spherical.
    pub fn is_cartesian(self) -> bool {
        matches!(self, DynamicsKind::Cartesian)
    }
}
