//! Scenario-file description of beacons (`[[beacons]]` tables), with validation and construction.
//!
//! ```toml
//! [[beacons]]
//! name = "surface-1"
//! kind = "surface"
//! position_km = [3300.0, 420.0, 1350.0]   # planet-fixed (seed 000 Table 2); OR lat_deg/lon_deg/altitude_km
//! range_sigma_m = 4.4721                  # optional 1σ two-way range noise
//! range_rate_sigma_mps = 0.1              # optional
//! outages = [[200.0, 300.0]]              # optional half-open [t_start_s, t_end_s): no measurement
//!
//! [[beacons]]
//! name = "orbiter-1"
//! kind = "orbiter"
//! elements = { a_km = 3700.0, e = 0.0, inc_deg = 90.0, raan_deg = 127.3, argp_deg = 0.0, true_anomaly_deg = 355.0 }
//! # OR position_km = [...] with velocity_mps = [...] (inertial at t = 0)
//! # OR circular = { altitude_km = 725.0, raan_deg = 49.329, inc_deg = 24.209, true_anomaly_deg = 240.219 }
//! ```
//!
//! Exactly one way of placing the beacon must be given. An outage may end at `inf` (e.g. seed
//! 000's fault case, where orbiter 2 gives no measurement after 200 s).

use super::elements::{CircularOrbit, KeplerElements};
use super::error::BeaconError;
use super::field_checks::check;
use super::orbiter::Orbiter;
use super::surface::SurfaceBeacon;
use super::visibility::Beacon;
use crate::planet::Planet;
use serde::{Deserialize, Serialize};

/// One beacon of a scenario, tagged by `kind = "surface" | "orbiter"`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "lowercase", deny_unknown_fields)]
pub enum BeaconConfig {
    /// A planet-fixed beacon.
    Surface(SurfaceBeaconConfig),
    /// An orbiter in two-body motion.
    Orbiter(OrbiterBeaconConfig),
}

/// Largest accepted 1σ range noise \[m\] (100 km).
pub const MAX_RANGE_SIGMA_M: f64 = 1e5;
/// Largest accepted 1σ range-rate noise [m/s] (1 km/s).
pub const MAX_RANGE_RATE_SIGMA_MPS: f64 = 1e3;

/// A planet-fixed beacon: `position_km`, or all of `lat_deg`, `lon_deg`, `altitude_km`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SurfaceBeaconConfig {
    /// Unique name, used in reports and measurement channel names.
    pub name: String,
    /// Planet-fixed position \[km\].
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        with = "crate::fixed_len::option_array"
    )]
    #[schemars(with = "Option<[f64; 3]>")]
    pub position_km: Option<[f64; 3]>,
    /// Planetocentric latitude \[deg\], in [−90, 90].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lat_deg: Option<f64>,
    /// East longitude \[deg\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lon_deg: Option<f64>,
    /// Altitude above the reference sphere \[km\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub altitude_km: Option<f64>,
    /// 1σ two-way range noise \[m\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub range_sigma_m: Option<f64>,
    /// 1σ range-rate noise [m/s].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub range_rate_sigma_mps: Option<f64>,
    /// Half-open intervals `[t_start_s, t_end_s)` without measurements.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub outages: Vec<[f64; 2]>,
    /// Elevation mask \[deg\] in [0, 90): the beacon measures only while the vehicle is at least
    /// this high above its horizon (default 0: seed 002 eq. 52's horizon).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elevation_mask_deg: Option<f64>,
}

/// An orbiter: `position_km` + `velocity_mps`, or `circular`, or `elements`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct OrbiterBeaconConfig {
    /// Unique name, used in reports and measurement channel names.
    pub name: String,
    /// Inertial position at t = 0 \[km\] (seed 000 Table 2).
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        with = "crate::fixed_len::option_array"
    )]
    #[schemars(with = "Option<[f64; 3]>")]
    pub position_km: Option<[f64; 3]>,
    /// Inertial velocity at t = 0 [m/s].
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        with = "crate::fixed_len::option_array"
    )]
    #[schemars(with = "Option<[f64; 3]>")]
    pub velocity_mps: Option<[f64; 3]>,
    /// Circular orbit of seed 002 eq. 55–56.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub circular: Option<CircularConfig>,
    /// Classical elements (seed 003 Table 3).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub elements: Option<ElementsConfig>,
    /// 1σ two-way range noise \[m\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub range_sigma_m: Option<f64>,
    /// 1σ range-rate noise [m/s].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub range_rate_sigma_mps: Option<f64>,
    /// Half-open intervals `[t_start_s, t_end_s)` without measurements.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub outages: Vec<[f64; 2]>,
}

/// Circular orbit in scenario units (seed 002 eq. 55–56).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CircularConfig {
    /// Altitude above the reference sphere \[km\], > 0.
    pub altitude_km: f64,
    /// Longitude of the ascending node Ω \[deg\].
    pub raan_deg: f64,
    /// Inclination i \[deg\], in [0, 180].
    pub inc_deg: f64,
    /// True anomaly (argument of latitude) f at t = 0 \[deg\].
    pub true_anomaly_deg: f64,
}

/// Classical elements of an elliptic orbit in scenario units.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ElementsConfig {
    /// Semi-major axis \[km\], > 0.
    pub a_km: f64,
    /// Eccentricity, in [0, 1).
    pub e: f64,
    /// Inclination \[deg\], in [0, 180].
    pub inc_deg: f64,
    /// Longitude of the ascending node Ω \[deg\].
    pub raan_deg: f64,
    /// Argument of periapsis ω \[deg\].
    pub argp_deg: f64,
    /// True anomaly f at t = 0 \[deg\].
    pub true_anomaly_deg: f64,
}

impl BeaconConfig {
    /// The beacon's name.
    pub fn name(&self) -> &str {
        match self {
            BeaconConfig::Surface(c) => &c.name,
            BeaconConfig::Orbiter(c) => &c.name,
        }
    }

    /// 1σ two-way range noise \[m\], if this beacon provides range.
    pub fn range_sigma_m(&self) -> Option<f64> {
        match self {
            BeaconConfig::Surface(c) => c.range_sigma_m,
            BeaconConfig::Orbiter(c) => c.range_sigma_m,
        }
    }

    /// 1σ range-rate noise [m/s], if this beacon provides range-rate.
    pub fn range_rate_sigma_mps(&self) -> Option<f64> {
        match self {
            BeaconConfig::Surface(c) => c.range_rate_sigma_mps,
            BeaconConfig::Orbiter(c) => c.range_rate_sigma_mps,
        }
    }

    /// Outage intervals `[t_start_s, t_end_s)`.
    pub fn outages(&self) -> &[[f64; 2]] {
        match self {
            BeaconConfig::Surface(c) => &c.outages,
            BeaconConfig::Orbiter(c) => &c.outages,
        }
    }

    /// Multiply the range and range-rate noise by `k` (trade-study noise scaling).
    pub fn scale_noise(&mut self, k: f64) {
        let (r, rr) = match self {
            BeaconConfig::Surface(c) => (&mut c.range_sigma_m, &mut c.range_rate_sigma_mps),
            BeaconConfig::Orbiter(c) => (&mut c.range_sigma_m, &mut c.range_rate_sigma_mps),
        };
        for v in [r, rr].into_iter().flatten() {
            *v *= k;
        }
    }

    /// Add an outage `[t_start_s, t_end_s)` (a beacon fault).
    pub fn add_outage(&mut self, t_start_s: f64, t_end_s: f64) {
        match self {
            BeaconConfig::Surface(c) => c.outages.push([t_start_s, t_end_s]),
            BeaconConfig::Orbiter(c) => c.outages.push([t_start_s, t_end_s]),
        }
    }

    /// Whether `t` \[s\] falls inside an outage (half-open: `t_start ≤ t < t_end`).
    pub fn in_outage(&self, t: f64) -> bool {
        self.outages().iter().any(|&[t0, t1]| t0 <= t && t < t1)
    }

    /// Check every field; errors name the field path under `field_prefix` (e.g. `beacons[2]`),
    /// the value and the allowed range. Planet-dependent checks (an orbiter's initial radius
    /// above the surface) happen in [`BeaconConfig::build`].
    pub fn validate(&self, field_prefix: &str) -> Result<(), BeaconError> {
        let p = field_prefix;
        if self.name().trim().is_empty() {
            return Err(BeaconError::invalid(
                format!("{p}.name"),
                self.name(),
                "a non-empty name",
            ));
        }
        // Physical envelopes: a 1σ above MAX_RANGE_SIGMA_M (MAX_RANGE_RATE_SIGMA_MPS) carries no
        // information about an entry (beacon ranges are at most a few thousand km, entry speeds
        // below 8 km/s) and overflows the squared noise of the filters (1e308 m made `simulate`
        // write ±inf).
        if let Some(s) = self.range_sigma_m() {
            check(
                &format!("{p}.range_sigma_m"),
                s,
                s > 0.0 && s <= MAX_RANGE_SIGMA_M,
                &format!("> 0 and <= {MAX_RANGE_SIGMA_M} m"),
            )?;
        }
        if let Some(s) = self.range_rate_sigma_mps() {
            let f = format!("{p}.range_rate_sigma_mps");
            check(
                &f,
                s,
                s > 0.0 && s <= MAX_RANGE_RATE_SIGMA_MPS,
                &format!("> 0 and <= {MAX_RANGE_RATE_SIGMA_MPS} m/s"),
            )?;
        }
        for (k, &[t0, t1]) in self.outages().iter().enumerate() {
            let f = format!("{p}.outages[{k}]");
            check(&format!("{f}[0]"), t0, t0 >= 0.0, "finite and >= 0 s")?;
            if t1.is_nan() || t1 <= t0 {
                return Err(BeaconError::invalid(
                    format!("{f}[1]"),
                    t1,
                    format!("> t_start = {t0} s (may be inf)"),
                ));
            }
        }
        match self {
            BeaconConfig::Surface(c) => c.validate_placement(p),
            BeaconConfig::Orbiter(c) => c.validate_placement(p),
        }
    }

    /// Validate (with field paths under `beacon "NAME"`) and build the beacon for `planet`.
    pub fn build(&self, planet: &Planet) -> Result<Beacon, BeaconError> {
        self.build_with_prefix(planet, &format!("beacon {:?}", self.name()))
    }

    /// As [`BeaconConfig::build`], with errors naming fields under `field_prefix`
    /// (e.g. `beacons[2]`).
    pub fn build_with_prefix(
        &self,
        planet: &Planet,
        field_prefix: &str,
    ) -> Result<Beacon, BeaconError> {
        self.validate(field_prefix)?;
        let p = field_prefix;
        match self {
            BeaconConfig::Surface(c) => {
                if let Some(pos) = c.position_km {
                    let pos_m = pos.map(|x| x * 1e3);
                    SurfaceBeacon::from_fixed_position(pos_m, planet)
                        .map_err(|e| e.in_context(&format!("{p}.position_km")))
                } else {
                    // validate() guarantees all three are present.
                    let (lat, lon, alt) = (
                        c.lat_deg.unwrap_or_default(),
                        c.lon_deg.unwrap_or_default(),
                        c.altitude_km.unwrap_or_default(),
                    );
                    SurfaceBeacon::from_lat_lon_alt(
                        lat.to_radians(),
                        lon.to_radians(),
                        alt * 1e3,
                        planet,
                    )
                    .map_err(|e| e.in_context(&format!("{p}.lat_deg/lon_deg/altitude_km")))
                }
                .and_then(|b| {
                    let mask = c.elevation_mask_deg.unwrap_or(0.0);
                    b.with_elevation_mask(mask.to_radians())
                        .map_err(|e| e.in_context(&format!("{p}.elevation_mask_deg")))
                })
                .map(Beacon::Surface)
            }
            BeaconConfig::Orbiter(c) => {
                let orbiter = if let Some(el) = &c.elements {
                    let elements = KeplerElements {
                        a: el.a_km * 1e3,
                        e: el.e,
                        inc: el.inc_deg.to_radians(),
                        raan: el.raan_deg.to_radians(),
                        argp: el.argp_deg.to_radians(),
                        true_anomaly: el.true_anomaly_deg.to_radians(),
                    };
                    Orbiter::from_elements(planet, &elements)
                        .map_err(|e| e.in_context(&format!("{p}.elements")))
                } else if let Some(ci) = &c.circular {
                    let orbit = CircularOrbit {
                        altitude: ci.altitude_km * 1e3,
                        raan: ci.raan_deg.to_radians(),
                        inc: ci.inc_deg.to_radians(),
                        true_anomaly: ci.true_anomaly_deg.to_radians(),
                    };
                    Orbiter::from_circular(planet, &orbit)
                        .map_err(|e| e.in_context(&format!("{p}.circular")))
                } else {
                    let r0 = c.position_km.unwrap_or_default().map(|x| x * 1e3);
                    let v0 = c.velocity_mps.unwrap_or_default();
                    Orbiter::from_state(planet, r0, v0)
                        .map_err(|e| e.in_context(&format!("{p}.position_km/velocity_mps")))
                }?;
                Ok(Beacon::Orbiter(orbiter))
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn outage_is_half_open() {
        let c = BeaconConfig::Surface(SurfaceBeaconConfig {
            name: "s".into(),
            position_km: Some([3300.0, 420.0, 1350.0]),
            outages: vec![[200.0, 300.0], [400.0, f64::INFINITY]],
            ..Default::default()
        });
        assert!(c.validate("beacons[0]").is_ok());
        assert!(!c.in_outage(199.999));
        assert!(c.in_outage(200.0));
        assert!(c.in_outage(299.999));
        assert!(!c.in_outage(300.0));
        assert!(c.in_outage(1e9));
    }

    #[test]
    fn partial_lat_lon_names_missing_fields() {
        let c = BeaconConfig::Surface(SurfaceBeaconConfig {
            name: "s".into(),
            lat_deg: Some(10.0),
            ..Default::default()
        });
        let e = c.validate("beacons[1]").unwrap_err().to_string();
        assert!(
            e.contains("beacons[1]") && e.contains("lon_deg") && e.contains("altitude_km"),
            "{e}"
        );
    }
}
