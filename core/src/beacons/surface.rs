//! Beacons fixed to the planet surface (or to any planet-fixed point).
//!
//! Seed 000 Table 2 gives two "surface" beacons as planet-frame positions in km with zero
//! velocity; seed 002 §5.1 places ground beacons by latitude and longitude. Both are stationary in
//! the planet-fixed frame, so in the inertial frame of [`crate::frames`] (which coincides with the
//! planet-fixed frame at t = 0) a beacon at planet-fixed position `r_f` is at
//!
//! `r_i(t) = R_z(ω t) r_f`,  `v_i(t) = ω ẑ × r_i(t)`.
//!
//! Seed 000 Table 2 lists the velocity as (0, 0, 0) — the planet-relative velocity; the inertial
//! velocity above is the same point seen from the non-rotating frame.

use super::error::{BeaconError, check_finite, check_finite3, check_planet};
use super::motion::BeaconMotion;
use crate::frames::{rotate_z, spherical_to_position};
use crate::math::norm;
use crate::planet::Planet;

/// A beacon fixed in the planet frame (seed 000 Table 2, seed 002 eq. 50–53).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct SurfaceBeacon {
    /// Planet-fixed position \[m\].
    position_fixed: [f64; 3],
    /// Planet rotation rate ω about +z [rad/s].
    rotation_rate: f64,
    /// Elevation mask \[rad\]: the beacon measures only while the vehicle is at least this
    /// high above its local horizon (0: eq. 52's horizon).
    elevation_mask: f64,
}

impl SurfaceBeacon {
    /// A beacon at the planet-fixed position `position_fixed` \[m\] (e.g. seed 000 Table 2 × 1000).
    ///
    /// The position must be finite and not at the planet centre; it is *not* required to lie on
    /// the reference sphere (seed 000's "surface" beacon 1 is ≈ 194 km above it).
    pub fn from_fixed_position(
        position_fixed: [f64; 3],
        planet: &Planet,
    ) -> Result<Self, BeaconError> {
        check_planet(planet)?;
        check_finite3("surface beacon position [m]", &position_fixed)?;
        let r = norm(&position_fixed);
        if r <= 0.0 {
            return Err(BeaconError::invalid(
                "surface beacon |position| [m]",
                r,
                "> 0 (not the planet centre)",
            ));
        }
        Ok(SurfaceBeacon {
            position_fixed,
            rotation_rate: planet.rotation_rate,
            elevation_mask: 0.0,
        })
    }

    /// The same beacon with an elevation mask of `mask` \[rad\] ∈ [0, π/2): it sees the vehicle
    /// only when the vehicle's elevation above its horizon exceeds the mask (terrain, multipath
    /// and antenna limits keep real ground stations above 5–10°).
    pub fn with_elevation_mask(mut self, mask: f64) -> Result<Self, BeaconError> {
        if !(mask.is_finite() && (0.0..std::f64::consts::FRAC_PI_2).contains(&mask)) {
            return Err(BeaconError::invalid(
                "surface beacon elevation mask [rad]",
                mask,
                "[0, pi/2)",
            ));
        }
        self.elevation_mask = mask;
        Ok(self)
    }

    /// The elevation mask \[rad\] (0: the horizon).
    pub fn elevation_mask(&self) -> f64 {
        self.elevation_mask
    }

    /// A beacon at planetocentric latitude `lat` \[rad\] ∈ [−π/2, π/2], longitude `lon` \[rad\] and
    /// altitude `altitude` \[m\] above the reference sphere (radius `planet.radius`).
    ///
    /// The altitude may be negative (depressions below the datum) but the radius `R + altitude`
    /// must stay positive.
    pub fn from_lat_lon_alt(
        lat: f64,
        lon: f64,
        altitude: f64,
        planet: &Planet,
    ) -> Result<Self, BeaconError> {
        check_planet(planet)?;
        check_finite("surface beacon latitude [rad]", lat)?;
        check_finite("surface beacon longitude [rad]", lon)?;
        check_finite("surface beacon altitude [m]", altitude)?;
        let half_pi = std::f64::consts::FRAC_PI_2;
        if !(-half_pi..=half_pi).contains(&lat) {
            return Err(BeaconError::invalid(
                "surface beacon latitude [rad]",
                lat,
                "[-pi/2, pi/2]",
            ));
        }
        let r = planet.radius + altitude;
        if r <= 0.0 {
            return Err(BeaconError::invalid(
                "surface beacon altitude [m]",
                altitude,
                format!("> -planet radius ({} m)", planet.radius),
            ));
        }
        Self::from_fixed_position(spherical_to_position(r, lon, lat), planet)
    }

    /// Planet-fixed position \[m\].
    pub fn position_fixed(&self) -> [f64; 3] {
        self.position_fixed
    }

    /// Rotation rate ω [rad/s] used to carry the beacon into the inertial frame.
    pub fn rotation_rate(&self) -> f64 {
        self.rotation_rate
    }

    /// Inertial position at time `t` \[s\]: the planet-fixed position rotated by ω·t about +z.
    #[inline]
    pub fn position_at(&self, t: f64) -> [f64; 3] {
        rotate_z(&self.position_fixed, self.rotation_rate * t)
    }
}

impl BeaconMotion for SurfaceBeacon {
    /// `r_i = R_z(ωt) r_f`, `v_i = ω ẑ × r_i = ω (−y_i, x_i, 0)`.
    #[inline]
    fn state_at(&self, t: f64) -> ([f64; 3], [f64; 3]) {
        let p = self.position_at(t);
        let w = self.rotation_rate;
        (p, [-w * p[1], w * p[0], 0.0])
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::{cross, dot};

    #[test]
    fn lat_lon_alt_radius_and_direction() {
        let mars = Planet::MARS;
        let b = SurfaceBeacon::from_lat_lon_alt(0.0, 0.0, 1000.0, &mars).unwrap();
        let p = b.position_fixed();
        assert!((p[0] - (mars.radius + 1000.0)).abs() < 1e-6);
        assert!(p[1].abs() < 1e-9 && p[2].abs() < 1e-9);
    }

    #[test]
    fn velocity_is_omega_cross_r() {
        let mars = Planet::MARS;
        let b = SurfaceBeacon::from_fixed_position([3_300e3, 420e3, 1_350e3], &mars).unwrap();
        let t = 1234.5;
        let (p, v) = b.state_at(t);
        let wv = cross(&[0.0, 0.0, mars.rotation_rate], &p);
        for k in 0..3 {
            assert!((v[k] - wv[k]).abs() < 1e-12);
        }
        assert!(dot(&p, &v).abs() < 1e-6);
    }

    #[test]
    fn rejects_bad_input() {
        let mars = Planet::MARS;
        assert!(SurfaceBeacon::from_fixed_position([0.0; 3], &mars).is_err());
        assert!(SurfaceBeacon::from_fixed_position([f64::NAN, 0.0, 1.0], &mars).is_err());
        assert!(SurfaceBeacon::from_lat_lon_alt(2.0, 0.0, 0.0, &mars).is_err());
        assert!(SurfaceBeacon::from_lat_lon_alt(0.0, 0.0, -4.0e6, &mars).is_err());
        let bad = Planet {
            rotation_rate: f64::INFINITY,
            ..mars
        };
        assert!(SurfaceBeacon::from_fixed_position([1.0, 0.0, 0.0], &bad).is_err());
    }
}
