//! Frames and coordinate conversions.
//!
//! * **Planet-fixed frame** (MCMF, seed 001 Fig. 1): origin at the planet centre, +z along the spin
//!   axis, +x through longitude 0.
//! * **Inertial frame**: coincides with the planet-fixed frame at t = 0 and does not rotate; the
//!   planet-fixed frame turns about +z by ω·t (seed 003 §1 uses the same Mars-centred inertial frame).
//! * **Spherical entry state** `[r, θ (lon), λ (lat), v, γ, ψ]` (seed 000 eq. 1, seed 001 eq. 1–6):
//!   v, γ, ψ describe the velocity *relative to the planet* in the local North-East-Up frame;
//!   γ is positive up; ψ is the heading measured **clockwise from north** (seeds 000, 001).
//!   Seed 002 measures the heading from east, counter-clockwise; [`HeadingConvention`] converts at
//!   the scenario boundary so the code has one convention.

use crate::math::{Real, V3, add, cross, dot, norm, scale};
use serde::{Deserialize, Serialize};

/// Which way a scenario's heading numbers are measured.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, Default, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum HeadingConvention {
    /// ψ = 0 due north, 90° due east (seeds 000 and 001); the internal convention.
    #[default]
    NorthClockwise,
    /// Ψ = 0 due east, 90° due north (seed 002 eq. 1).
    EastCounterclockwise,
}

impl HeadingConvention {
    /// Convert a heading in this convention to the internal north-clockwise heading \[rad\].
    pub fn to_internal(self, heading: f64) -> f64 {
        match self {
            HeadingConvention::NorthClockwise => heading,
            HeadingConvention::EastCounterclockwise => std::f64::consts::FRAC_PI_2 - heading,
        }
    }

    /// Convert an internal north-clockwise heading \[rad\] to this convention.
    pub fn from_internal(self, heading: f64) -> f64 {
        // The map ψ ↦ π/2 − ψ is its own inverse.
        self.to_internal(heading)
    }
}

/// Local East, North, Up unit vectors (planet-fixed components) at longitude `lon`, latitude `lat`.
pub fn enu_basis<T: Real>(lon: T, lat: T) -> [V3<T>; 3] {
    let (so, co) = (lon.sin(), lon.cos());
    let (sa, ca) = (lat.sin(), lat.cos());
    let zero = T::from(0.0);
    [
        [-so, co, zero],
        [-sa * co, -sa * so, ca],
        [ca * co, ca * so, sa],
    ]
}

/// Planet-fixed position from radius, longitude and latitude.
pub fn spherical_to_position<T: Real>(r: T, lon: T, lat: T) -> V3<T> {
    let ca = lat.cos();
    [r * ca * lon.cos(), r * ca * lon.sin(), r * lat.sin()]
}

/// Radius, longitude, latitude of a position.
pub fn position_to_spherical<T: Real>(p: &V3<T>) -> (T, T, T) {
    let r = norm(p);
    let lon = p[1].atan2(p[0]);
    let lat = (p[2] / r).asin();
    (r, lon, lat)
}

/// Velocity vector (planet-fixed components) from speed, flight-path angle and north-clockwise heading.
pub fn velocity_from_angles<T: Real>(lon: T, lat: T, v: T, fpa: T, heading: T) -> V3<T> {
    let [e, n, u] = enu_basis(lon, lat);
    let ch = fpa.cos();
    let ce = v * ch * heading.sin();
    let cn = v * ch * heading.cos();
    let cu = v * fpa.sin();
    add(&add(&scale(ce, &e), &scale(cn, &n)), &scale(cu, &u))
}

/// Rotate a vector about +z by `angle` (active rotation).
pub fn rotate_z<T: Real>(a: &V3<T>, angle: T) -> V3<T> {
    let (s, c) = (angle.sin(), angle.cos());
    [c * a[0] - s * a[1], s * a[0] + c * a[1], a[2]]
}

/// A spherical entry state `[r, lon, lat, v, fpa, heading]` in SI units (internal heading convention).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct SphericalState {
    /// Radius from the planet centre \[m\].
    pub r: f64,
    /// Longitude θ \[rad\].
    pub lon: f64,
    /// Latitude λ \[rad\].
    pub lat: f64,
    /// Planet-relative speed [m/s].
    pub v: f64,
    /// Flight-path angle γ \[rad\], positive up.
    pub fpa: f64,
    /// Heading ψ \[rad\], clockwise from north.
    pub heading: f64,
}

impl SphericalState {
    /// As the array `[r, lon, lat, v, fpa, heading]`.
    pub fn to_array(&self) -> [f64; 6] {
        [self.r, self.lon, self.lat, self.v, self.fpa, self.heading]
    }

    /// From the array `[r, lon, lat, v, fpa, heading]`.
    pub fn from_array(a: &[f64; 6]) -> Self {
        SphericalState {
            r: a[0],
            lon: a[1],
            lat: a[2],
            v: a[3],
            fpa: a[4],
            heading: a[5],
        }
    }
}

/// Planet-fixed position and planet-relative velocity of a spherical state.
pub fn spherical_to_fixed<T: Real>(x: &[T; 6]) -> (V3<T>, V3<T>) {
    let pos = spherical_to_position(x[0], x[1], x[2]);
    let vel = velocity_from_angles(x[1], x[2], x[3], x[4], x[5]);
    (pos, vel)
}

/// Inertial position and velocity at time `t` of a spherical (planet-relative) state.
///
/// `v_i = R_z(ωt) (v_rel + ω ẑ × r_f)`, `r_i = R_z(ωt) r_f`.
pub fn spherical_to_inertial<T: Real>(x: &[T; 6], t: f64, omega: f64) -> (V3<T>, V3<T>) {
    let (pf, vf) = spherical_to_fixed(x);
    fixed_to_inertial(&pf, &vf, t, omega)
}

/// Inertial position and velocity at time `t` of a planet-fixed position `pf` and
/// planet-relative velocity `vf`: `r_i = R_z(ωt) r_f`, `v_i = R_z(ωt) (v_f + ω ẑ × r_f)`.
pub fn fixed_to_inertial<T: Real>(pf: &V3<T>, vf: &V3<T>, t: f64, omega: f64) -> (V3<T>, V3<T>) {
    let w = [T::from(0.0), T::from(0.0), T::from(omega)];
    let vin = add(vf, &cross(&w, pf));
    let ang = T::from(omega * t);
    (rotate_z(pf, ang), rotate_z(&vin, ang))
}

/// Spherical (planet-relative) state from inertial position and velocity at time `t`.
pub fn inertial_to_spherical<T: Real>(pos: &V3<T>, vel: &V3<T>, t: f64, omega: f64) -> [T; 6] {
    let ang = T::from(-omega * t);
    let pf = rotate_z(pos, ang);
    let vi_f = rotate_z(vel, ang);
    let w = [T::from(0.0), T::from(0.0), T::from(omega)];
    let vf = crate::math::sub(&vi_f, &cross(&w, &pf));
    fixed_to_spherical(&pf, &vf)
}

/// Spherical state from planet-fixed position and planet-relative velocity.
pub fn fixed_to_spherical<T: Real>(pf: &V3<T>, vf: &V3<T>) -> [T; 6] {
    let (r, lon, lat) = position_to_spherical(pf);
    let [e, n, u] = enu_basis(lon, lat);
    let v = norm(vf);
    let fpa = (dot(vf, &u) / v).asin();
    let heading = dot(vf, &e).atan2(dot(vf, &n));
    [r, lon, lat, v, fpa, heading]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn round_trip_inertial_spherical() {
        let x: [f64; 6] = [3_518_200.0, -1.5686, -0.489, 5515.0, -0.2059, 0.09];
        for &(t, w) in &[(0.0, 0.0), (123.4, 7.0882e-5)] {
            let (p, v) = spherical_to_inertial(&x, t, w);
            let y = inertial_to_spherical(&p, &v, t, w);
            for k in 0..6 {
                assert!(
                    (x[k] - y[k]).abs() < 1e-9 * x[k].abs().max(1.0),
                    "k={k} {} vs {}",
                    x[k],
                    y[k]
                );
            }
        }
    }

    #[test]
    fn heading_east_is_plus_x_at_origin() {
        // At lon = lat = 0, east is +y of the planet-fixed frame.
        let v = velocity_from_angles(0.0, 0.0, 1.0, 0.0, std::f64::consts::FRAC_PI_2);
        assert!((v[1] - 1.0).abs() < 1e-15 && v[0].abs() < 1e-15);
    }

    #[test]
    fn east_convention_converts() {
        let c = HeadingConvention::EastCounterclockwise;
        assert!((c.to_internal(0.0) - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
        assert!((c.from_internal(c.to_internal(0.3)) - 0.3).abs() < 1e-15);
    }
}
