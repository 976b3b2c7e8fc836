//! Line-of-sight visibility between the vehicle and a beacon, and the [`Beacon`] enum.
//!
//! * Ground (planet-fixed) beacons — seed 002 eq. 50–52: with `n_B` the unit vector along the
//!   beacon position and `n_C` the unit vector from the beacon to the vehicle (eq. 51: vehicle −
//!   beacon), the beacon is visible iff `arccos(n_B · n_C) < π/2`, i.e. the vehicle is above the
//!   beacon's local horizontal plane.
//! * Orbiters — seed 002 eq. 58–60: `θ0 = arccos(R/|r|)`, `θ1 = arccos(R/|r_B|)`,
//!   `θ = ∠(r, r_B)`; visible iff `θ < θ0 + θ1` (the straight line between the two does not dip
//!   into the reference sphere).
//!
//! Each test comes with a *margin* in radians, positive when visible and negative when not, which
//! is continuous in the positions (useful as an optimizer constraint). Angles are computed with
//! `atan2(|a × b|, a · b)`, which is accurate near 0 and π where `arccos` is not. Positions passed
//! in must be in the same (inertial) frame; finite inputs always give finite margins.

use super::motion::BeaconMotion;
use super::orbiter::Orbiter;
use super::surface::SurfaceBeacon;
use crate::math::{cross, dot, norm, sub};

/// Angle between two vectors \[rad\] ∈ [0, π]; 0 if either is zero.
#[inline]
fn angle_between(a: &[f64; 3], b: &[f64; 3]) -> f64 {
    norm(&cross(a, b)).atan2(dot(a, b))
}

/// Horizon half-angle `arccos(R/d)` of seed 002 eq. 58, with `R/d` clamped to [−1, 1] so that a
/// point inside the sphere (d < R, including d = 0) gets 0 instead of NaN.
#[inline]
fn horizon_angle(radius: f64, distance: f64) -> f64 {
    let ratio = radius / distance;
    if ratio.is_nan() {
        // 0/0: a point at the centre of a zero-radius body.
        return 0.0;
    }
    ratio.clamp(-1.0, 1.0).acos()
}

/// Ground-beacon visibility margin \[rad\], seed 002 eq. 50–52: `π/2 − ∠(n_B, n_C)` where `n_B`
/// points along the beacon position and `n_C` from the beacon to the vehicle.
///
/// Positive iff `n_B · n_C > 0`; in [−π/2, π/2]. If the vehicle is exactly at the beacon the margin
/// is 0 (not visible).
pub fn ground_visibility_margin(beacon_pos: &[f64; 3], vehicle_pos: &[f64; 3]) -> f64 {
    let to_vehicle = sub(vehicle_pos, beacon_pos);
    // atan2(n_B·n_C, |n_B × n_C|) = π/2 − ∠(n_B, n_C); normalising both vectors does not change it.
    dot(beacon_pos, &to_vehicle).atan2(norm(&cross(beacon_pos, &to_vehicle)))
}

/// Ground-beacon visibility, seed 002 eq. 52: `arccos(n_B · n_C) < π/2`.
pub fn ground_visible(beacon_pos: &[f64; 3], vehicle_pos: &[f64; 3]) -> bool {
    ground_visibility_margin(beacon_pos, vehicle_pos) > 0.0
}

/// Orbiter visibility margin \[rad\], seed 002 eq. 58–60: `θ0 + θ1 − θ`.
///
/// `θ0 = arccos(R/|r|)` (vehicle), `θ1 = arccos(R/|r_B|)` (orbiter), `θ = ∠(r, r_B)`. A position
/// below the reference sphere has a horizon angle of 0 (the ratio is clamped), never NaN.
pub fn orbiter_visibility_margin(
    orbiter_pos: &[f64; 3],
    vehicle_pos: &[f64; 3],
    planet_radius: f64,
) -> f64 {
    let theta0 = horizon_angle(planet_radius, norm(vehicle_pos));
    let theta1 = horizon_angle(planet_radius, norm(orbiter_pos));
    theta0 + theta1 - angle_between(vehicle_pos, orbiter_pos)
}

/// Orbiter visibility, seed 002 eq. 60: `θ < θ0 + θ1`.
pub fn orbiter_visible(orbiter_pos: &[f64; 3], vehicle_pos: &[f64; 3], planet_radius: f64) -> bool {
    orbiter_visibility_margin(orbiter_pos, vehicle_pos, planet_radius) > 0.0
}

/// Any beacon the navigation system can range to.
#[derive(Debug, Clone, PartialEq)]
pub enum Beacon {
    /// Fixed to the planet; visibility by seed 002 eq. 50–52.
    Surface(SurfaceBeacon),
    /// In two-body orbit; visibility by seed 002 eq. 58–60.
    Orbiter(Orbiter),
}

impl Beacon {
    /// Inertial position \[m\] at time `t` \[s\] (cheaper than [`BeaconMotion::state_at`] for
    /// surface beacons).
    pub fn position_at(&self, t: f64) -> [f64; 3] {
        match self {
            Beacon::Surface(b) => b.position_at(t),
            Beacon::Orbiter(o) => o.state_at(t).0,
        }
    }

    /// Whether this is an orbiter.
    pub fn is_orbiter(&self) -> bool {
        matches!(self, Beacon::Orbiter(_))
    }

    /// Visibility margin \[rad\] from a vehicle at inertial position `vehicle_pos_inertial` \[m\] at
    /// time `t` \[s\]: [`ground_visibility_margin`] less the beacon's elevation mask for surface
    /// beacons, [`orbiter_visibility_margin`] for orbiters. Positive = visible.
    pub fn visibility_margin(
        &self,
        vehicle_pos_inertial: [f64; 3],
        t: f64,
        planet_radius: f64,
    ) -> f64 {
        self.visibility_margin_from(&self.position_at(t), vehicle_pos_inertial, planet_radius)
    }

    /// [`Beacon::visibility_margin`] with the beacon's inertial position `beacon_pos` at that
    /// time already known (e.g. from the scenario's [`super::EphemerisTable`]).
    pub fn visibility_margin_from(
        &self,
        beacon_pos: &[f64; 3],
        vehicle_pos_inertial: [f64; 3],
        planet_radius: f64,
    ) -> f64 {
        let b = beacon_pos;
        match self {
            Beacon::Surface(s) => {
                ground_visibility_margin(b, &vehicle_pos_inertial) - s.elevation_mask()
            }
            Beacon::Orbiter(_) => {
                orbiter_visibility_margin(b, &vehicle_pos_inertial, planet_radius)
            }
        }
    }

    /// Line of sight from a vehicle at inertial position `vehicle_pos_inertial` \[m\] at time `t`
    /// \[s\], by the test appropriate to the beacon type (seed 002 eq. 52 or eq. 60).
    /// `planet_radius` \[m\] is used only for orbiters. Non-finite input gives `false`.
    pub fn visible_from(&self, vehicle_pos_inertial: [f64; 3], t: f64, planet_radius: f64) -> bool {
        self.visibility_margin(vehicle_pos_inertial, t, planet_radius) > 0.0
    }
}

impl BeaconMotion for Beacon {
    fn state_at(&self, t: f64) -> ([f64; 3], [f64; 3]) {
        match self {
            Beacon::Surface(b) => b.state_at(t),
            Beacon::Orbiter(o) => o.state_at(t),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const R: f64 = 3_396_200.0;

    #[test]
    fn ground_margin_is_elevation_of_vehicle() {
        let b = [R, 0.0, 0.0];
        // Vehicle 45° above the local horizon of the beacon.
        let v = [R + 100e3, 100e3, 0.0];
        let m = ground_visibility_margin(&b, &v);
        assert!((m - std::f64::consts::FRAC_PI_4).abs() < 1e-12);
        assert!(ground_visible(&b, &v));
        assert!(!ground_visible(&b, &[R - 1.0, 1e6, 0.0]));
        assert_eq!(ground_visibility_margin(&b, &b), 0.0);
    }

    #[test]
    fn orbiter_margin_never_nan() {
        let inside = [1000.0, 0.0, 0.0];
        let m = orbiter_visibility_margin(&[R + 500e3, 0.0, 0.0], &inside, R);
        assert!(m.is_finite());
        let m0 = orbiter_visibility_margin(&[R + 500e3, 0.0, 0.0], &[0.0; 3], R);
        assert!(m0.is_finite());
        let m00 = orbiter_visibility_margin(&[0.0; 3], &[0.0; 3], 0.0);
        assert!(m00.is_finite());
    }
}
