//! The surface [`Target`] and the great-circle geometry guidance measures against it: central
//! angle, bearing, destination, range-to-go and crossrange.

use super::nav_state::NavState;

/// A surface target (deployment point).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Target {
    /// Latitude \[rad\].
    pub lat: f64,
    /// Longitude \[rad\].
    pub lon: f64,
}

/// Great-circle angle between two points \[rad\] (haversine form).
pub fn central_angle(lat1: f64, lon1: f64, lat2: f64, lon2: f64) -> f64 {
    let a = ((lat2 - lat1) / 2.0).sin().powi(2)
        + lat1.cos() * lat2.cos() * ((lon2 - lon1) / 2.0).sin().powi(2);
    2.0 * a.sqrt().min(1.0).asin()
}

/// Initial bearing from point 1 to point 2 \[rad\], north-clockwise.
pub fn bearing(lat1: f64, lon1: f64, lat2: f64, lon2: f64) -> f64 {
    let dl = lon2 - lon1;
    (dl.sin() * lat2.cos()).atan2(lat1.cos() * lat2.sin() - lat1.sin() * lat2.cos() * dl.cos())
}

/// The point reached from (lat, lon) along bearing `psi` (north-clockwise) over central angle `d`.
pub fn destination(lat: f64, lon: f64, psi: f64, d: f64) -> Target {
    let lat2 = (lat.sin() * d.cos() + lat.cos() * d.sin() * psi.cos()).asin();
    let lon2 = lon + (psi.sin() * d.sin() * lat.cos()).atan2(d.cos() - lat.sin() * lat2.sin());
    Target {
        lat: lat2,
        lon: lon2,
    }
}

/// Range-to-go and crossrange of `target` from the vehicle, as central angles \[rad\]: the
/// great-circle angle to the target, and asin(sin d · sin(β − ψ)) for bearing β and heading ψ
/// (positive: the target lies to the right of the velocity's great circle).
pub fn range_crossrange(nav: &NavState, target: &Target) -> (f64, f64) {
    let [_, lon, lat, _, _, psi] = nav.spherical;
    let d = central_angle(lat, lon, target.lat, target.lon);
    let b = bearing(lat, lon, target.lat, target.lon);
    (d, (d.sin() * (b - psi).sin()).asin())
}
