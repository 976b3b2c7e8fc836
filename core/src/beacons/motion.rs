//! [`BeaconMotion`]: the motion of one beacon, queried in the inertial frame.

/// The motion of one beacon, queried in the inertial frame (see [`crate::frames`]).
pub trait BeaconMotion {
    /// Inertial position \[m\] and velocity [m/s] at time `t` \[s\] since the scenario epoch.
    fn state_at(&self, t: f64) -> ([f64; 3], [f64; 3]);
}
