//! [`Site`]: a ground site (latitude, longitude, altitude).

use entrynav::frames::position_to_spherical;
use entrynav::frames::spherical_to_position;

/// A ground site (radians, metres).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Site {
    /// Planetocentric latitude \[rad\].
    pub lat: f64,
    /// East longitude \[rad\].
    pub lon: f64,
    /// Altitude above the reference sphere \[m\].
    pub altitude_m: f64,
}

impl Site {
    /// From degrees, on the reference sphere.
    pub fn from_degrees(lat_deg: f64, lon_deg: f64) -> Site {
        Site {
            lat: lat_deg.to_radians(),
            lon: lon_deg.to_radians(),
            altitude_m: 0.0,
        }
    }

    /// [latitude, longitude] in degrees.
    pub fn degrees(&self) -> [f64; 2] {
        [self.lat.to_degrees(), self.lon.to_degrees()]
    }

    /// The same point with latitude in [−π/2, π/2] and longitude in (−π, π].
    pub fn canonical(&self) -> Site {
        let p = spherical_to_position(1.0, self.lon, self.lat);
        let (_, lon, lat) = position_to_spherical(&p);
        Site {
            lat,
            lon,
            altitude_m: self.altitude_m,
        }
    }

    /// Planet-fixed position \[m\] for reference radius `radius`.
    pub fn fixed_position(&self, radius: f64) -> [f64; 3] {
        spherical_to_position(radius + self.altitude_m, self.lon, self.lat)
    }
}
