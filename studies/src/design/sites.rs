//! The input design of a scenario as the optimizer sees it — its surface beacons as sites with
//! their elevation mask, its circular orbiters as elements — and how sites and elements appear in
//! a design's JSON.

use entrynav::beacons::BeaconConfig;
use entrynav::scenario::ScenarioConfig;
use entrynav_optimizer::{OrbitElements, Site};
use serde_json::{Value, json};

/// The scenario's surface beacons as sites (lat/lon/altitude or planet-fixed position).
pub fn scenario_sites(cfg: &ScenarioConfig) -> Vec<Site> {
    let radius = cfg.planet.resolve().radius;
    cfg.beacons
        .iter()
        .filter_map(|b| match b {
            BeaconConfig::Surface(s) => match (s.lat_deg, s.lon_deg, s.position_km) {
                (Some(lat), Some(lon), _) => Some(Site {
                    altitude_m: s.altitude_km.unwrap_or(0.0) * 1e3,
                    ..Site::from_degrees(lat, lon)
                }),
                (_, _, Some(p)) => {
                    let p = p.map(|c| c * 1e3);
                    let (r, lon, lat) = entrynav::frames::position_to_spherical(&p);
                    Some(Site {
                        lat,
                        lon,
                        altitude_m: r - radius,
                    })
                }
                _ => None,
            },
            BeaconConfig::Orbiter(_) => None,
        })
        .collect()
}

/// The elevation mask of the scenario's surface beacons \[deg\] (the first one's; 0: the
/// horizon).
pub fn scenario_mask_deg(cfg: &ScenarioConfig) -> f64 {
    cfg.beacons
        .iter()
        .find_map(|b| match b {
            BeaconConfig::Surface(c) => Some(c.elevation_mask_deg.unwrap_or(0.0)),
            BeaconConfig::Orbiter(_) => None,
        })
        .unwrap_or(0.0)
}

/// The scenario's own orbiters on circular orbits: (altitude \[m\], elements).
pub fn scenario_orbits(cfg: &ScenarioConfig) -> Vec<(f64, OrbitElements)> {
    cfg.beacons
        .iter()
        .filter_map(|b| match b {
            BeaconConfig::Orbiter(o) => o.circular.map(|c| {
                (
                    c.altitude_km * 1e3,
                    OrbitElements::from_degrees(c.raan_deg, c.inc_deg, c.true_anomaly_deg),
                )
            }),
            BeaconConfig::Surface(_) => None,
        })
        .collect()
}

/// Sites as `[{lat_deg, lon_deg}]`.
pub fn sites_json(sites: &[Site]) -> Value {
    Value::Array(
        sites
            .iter()
            .map(|s| {
                let [lat, lon] = s.degrees();
                json!({"lat_deg": lat, "lon_deg": lon})
            })
            .collect(),
    )
}

/// The elements of each orbiter in degrees.
pub fn elements_json(el: &[OrbitElements]) -> Value {
    Value::Array(
        el.iter()
            .map(|e| {
                let [raan, inc, f] = e.degrees();
                json!({"raan_deg": raan, "inc_deg": inc, "true_anomaly_deg": f})
            })
            .collect(),
    )
}

/// The `indices` of `sites` chosen.
pub fn chosen(sites: &[Site], indices: &[usize]) -> Vec<Site> {
    indices.iter().map(|&i| sites[i]).collect()
}
