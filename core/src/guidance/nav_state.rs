//! [`NavState`]: the navigation solution guidance is given each cycle, never the truth.

use super::error::GuidanceError;
use crate::frames::inertial_to_spherical;

/// The navigation solution guidance is given each cycle: the onboard estimate, in the planet
/// frame, never the truth type. Build it from a filter's state with [`NavState::from_estimate`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct NavState {
    /// Time \[s\].
    pub t: f64,
    /// Planet-relative spherical state `[r, lon, lat, v, fpa, heading]` (SI, rad, heading
    /// north-clockwise), the state order of the spherical filters.
    pub spherical: [f64; 6],
    /// Drag acceleration sensed by the accelerometers \[m/s²\] (the IMU's along-velocity specific
    /// force; Apollo compares it with the reference drag).
    pub drag_mps2: f64,
}

impl NavState {
    /// From the six kinematic states of a filter estimate (`cartesian`: inertial
    /// `[x, y, z, vx, vy, vz]` on a planet rotating at `omega`; otherwise already spherical and
    /// planet-relative) at time `t`, with the sensed drag.
    pub fn from_estimate(
        x: &[f64],
        cartesian: bool,
        t: f64,
        omega: f64,
        drag_mps2: f64,
    ) -> Result<Self, GuidanceError> {
        if x.len() < 6 || !x[..6].iter().all(|v| v.is_finite()) {
            return Err(GuidanceError::BadNavigation {
                t_s: t,
                what: "fewer than six finite kinematic states",
            });
        }
        let spherical = if cartesian {
            inertial_to_spherical(&[x[0], x[1], x[2]], &[x[3], x[4], x[5]], t, omega)
        } else {
            [x[0], x[1], x[2], x[3], x[4], x[5]]
        };
        Ok(NavState {
            t,
            spherical,
            drag_mps2,
        })
    }

    /// Speed \[m/s\].
    pub fn speed(&self) -> f64 {
        self.spherical[3]
    }

    /// Altitude rate ṙ = v sinγ \[m/s\].
    pub fn rdot(&self) -> f64 {
        self.spherical[3] * self.spherical[4].sin()
    }
}
