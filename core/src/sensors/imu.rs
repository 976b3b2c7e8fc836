//! Accelerometer (IMU specific force) model.

use crate::math::{Real, V3};
use serde::{Deserialize, Serialize};

/// Frame in which the accelerometer reports specific force.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "frame", rename_all = "kebab-case")]
pub enum ImuFrame {
    /// Velocity (wind) frame: `[−D, −L sinσ, L cosσ]` (seed 000 eq. 5, seed 003 eq. 7).
    Velocity,
    /// Body frame rotated from the velocity frame by the angle of attack α about the wind-frame
    /// y axis (seed 001 eq. 12: ã^b = T_v^b a^v).
    Body {
        /// Angle of attack α \[rad\] (MSL trim: −17°, seed 001 §V.A).
        angle_of_attack: f64,
    },
}

/// `T_v^b a^v`: rotate a velocity-frame vector into the body frame by the angle of attack α
/// about y: `a^b = [cosα·a_x − sinα·a_z, a_y, sinα·a_x + cosα·a_z]`.
///
/// Seed 001 does not print T_v^b; we use the frame rotation about the common y axis (body x on the
/// axis of symmetry, at α from the airspeed vector). Truth and filters share this definition.
#[inline]
pub fn body_from_velocity<T: Real>(a: &V3<T>, alpha: f64) -> V3<T> {
    let (s, c) = alpha.sin_cos();
    [a[0] * c - a[2] * s, a[1], a[0] * s + a[2] * c]
}

impl ImuFrame {
    /// Express a velocity-frame specific force in this frame.
    pub fn express<T: Real>(&self, a_v: &V3<T>) -> V3<T> {
        match self {
            ImuFrame::Velocity => *a_v,
            ImuFrame::Body { angle_of_attack } => body_from_velocity(a_v, *angle_of_attack),
        }
    }

    /// The drag acceleration D \[m/s²\] in a triad `a` read in this frame: minus the wind-frame x
    /// component (`[−D, −L sinσ, L cosσ]`, seed 000 eq. 5), the inverse of
    /// [`ImuFrame::express`] (`a_x^v = cosα·a_x^b + sinα·a_z^b`). What an entry vehicle's guidance
    /// calls the sensed drag.
    pub fn drag_from(&self, a: &V3<f64>) -> f64 {
        match self {
            ImuFrame::Velocity => -a[0],
            ImuFrame::Body { angle_of_attack } => {
                let (s, c) = angle_of_attack.sin_cos();
                -(c * a[0] + s * a[2])
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn body_rotation_preserves_norm_and_is_identity_at_zero() {
        let a = [-10.0, 0.5, 2.4];
        let b = body_from_velocity(&a, -17f64.to_radians());
        let n = |v: &[f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
        assert!((n(&a) - n(&b)).abs() < 1e-12);
        assert_eq!(body_from_velocity(&a, 0.0), a);
    }

    #[test]
    fn drag_from_inverts_express() {
        let a_v = [-10.0, 0.5, 2.4];
        for f in [
            ImuFrame::Velocity,
            ImuFrame::Body {
                angle_of_attack: -17f64.to_radians(),
            },
        ] {
            assert!((f.drag_from(&f.express(&a_v)) - 10.0).abs() < 1e-12);
        }
    }
}
