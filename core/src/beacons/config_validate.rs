//! Placement checks behind [`super::BeaconConfig::validate`]: which of the mutually exclusive ways
//! of placing a beacon was given, and whether its numbers are in range. Errors name the field path.

use super::config::{OrbiterBeaconConfig, SurfaceBeaconConfig};
use super::error::BeaconError;
use super::field_checks::{check, check3, choice};

impl SurfaceBeaconConfig {
    pub(super) fn validate_placement(&self, p: &str) -> Result<(), BeaconError> {
        if let Some(m) = self.elevation_mask_deg {
            check(
                &format!("{p}.elevation_mask_deg"),
                m,
                (0.0..90.0).contains(&m),
                "[0, 90) deg",
            )?;
        }
        let geo = [
            ("lat_deg", self.lat_deg),
            ("lon_deg", self.lon_deg),
            ("altitude_km", self.altitude_km),
        ];
        let given: Vec<&str> = geo.iter().filter(|g| g.1.is_some()).map(|g| g.0).collect();
        match (self.position_km, given.len()) {
            (Some(pos), 0) => {
                let f = format!("{p}.position_km");
                check3(&f, &pos)?;
                if pos.iter().all(|&x| x == 0.0) {
                    return Err(BeaconError::invalid(f, pos, "not the planet centre"));
                }
                Ok(())
            }
            (None, 3) => {
                let lat = self.lat_deg.unwrap_or_default();
                let f = format!("{p}.lat_deg");
                check(&f, lat, (-90.0..=90.0).contains(&lat), "[-90, 90] deg")?;
                let lon = self.lon_deg.unwrap_or_default();
                check(
                    &format!("{p}.lon_deg"),
                    lon,
                    true,
                    "a finite number of degrees",
                )?;
                let alt = self.altitude_km.unwrap_or_default();
                check(
                    &format!("{p}.altitude_km"),
                    alt,
                    true,
                    "a finite number of km",
                )
            }
            (Some(_), _) => Err(choice(
                p,
                format!(
                    "give either `position_km` or `lat_deg`/`lon_deg`/`altitude_km`, not both \
                     (found position_km and {})",
                    given.join(", ")
                ),
            )),
            (None, 0) => Err(choice(
                p,
                "a surface beacon needs `position_km` or all of `lat_deg`, `lon_deg`, \
                 `altitude_km`"
                    .to_string(),
            )),
            (None, _) => {
                let missing: Vec<&str> =
                    geo.iter().filter(|g| g.1.is_none()).map(|g| g.0).collect();
                Err(choice(
                    p,
                    format!(
                        "`lat_deg`, `lon_deg` and `altitude_km` go together; missing {}",
                        missing.join(", ")
                    ),
                ))
            }
        }
    }
}

impl OrbiterBeaconConfig {
    pub(super) fn validate_placement(&self, p: &str) -> Result<(), BeaconError> {
        let state = self.position_km.is_some() || self.velocity_mps.is_some();
        let mut given = Vec::new();
        if state {
            given.push("position_km/velocity_mps");
        }
        if self.circular.is_some() {
            given.push("circular");
        }
        if self.elements.is_some() {
            given.push("elements");
        }
        if given.len() != 1 {
            let found = if given.is_empty() {
                "none".to_string()
            } else {
                given.join(" and ")
            };
            return Err(choice(
                p,
                format!(
                    "give exactly one of `position_km` + `velocity_mps`, `circular`, `elements` \
                     (found {found})"
                ),
            ));
        }
        if state {
            let (Some(pos), Some(vel)) = (self.position_km, self.velocity_mps) else {
                let missing = if self.position_km.is_none() {
                    "position_km"
                } else {
                    "velocity_mps"
                };
                return Err(choice(
                    p,
                    format!("`position_km` and `velocity_mps` go together; missing {missing}"),
                ));
            };
            check3(&format!("{p}.position_km"), &pos)?;
            check3(&format!("{p}.velocity_mps"), &vel)?;
        }
        let inc_ok = |i: f64| (0.0..=180.0).contains(&i);
        if let Some(c) = &self.circular {
            let f = format!("{p}.circular");
            check(
                &format!("{f}.altitude_km"),
                c.altitude_km,
                c.altitude_km > 0.0,
                "> 0 km",
            )?;
            check(
                &format!("{f}.raan_deg"),
                c.raan_deg,
                true,
                "a finite number of degrees",
            )?;
            check(
                &format!("{f}.inc_deg"),
                c.inc_deg,
                inc_ok(c.inc_deg),
                "[0, 180] deg",
            )?;
            let ta = c.true_anomaly_deg;
            check(
                &format!("{f}.true_anomaly_deg"),
                ta,
                true,
                "a finite number of degrees",
            )?;
        }
        if let Some(el) = &self.elements {
            let f = format!("{p}.elements");
            check(&format!("{f}.a_km"), el.a_km, el.a_km > 0.0, "> 0 km")?;
            check(
                &format!("{f}.e"),
                el.e,
                (0.0..1.0).contains(&el.e),
                "[0, 1)",
            )?;
            check(
                &format!("{f}.inc_deg"),
                el.inc_deg,
                inc_ok(el.inc_deg),
                "[0, 180] deg",
            )?;
            for (name, v) in [
                ("raan_deg", el.raan_deg),
                ("argp_deg", el.argp_deg),
                ("true_anomaly_deg", el.true_anomaly_deg),
            ] {
                check(
                    &format!("{f}.{name}"),
                    v,
                    true,
                    "a finite number of degrees",
                )?;
            }
        }
        Ok(())
    }
}
