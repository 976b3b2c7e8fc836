//! Scenario files carrying an optimized geometry: the base scenario with its beacons replaced,
//! serialised to TOML and validated by [`ScenarioConfig::from_toml_str`] (so `entrynav trade` and
//! every other command accept them).

use crate::error::OptimizerError;
use crate::ground::site::Site;
use crate::orbiters::OrbitElements;
use entrynav::beacons::{BeaconConfig, CircularConfig, OrbiterBeaconConfig, SurfaceBeaconConfig};
use entrynav::scenario::ScenarioConfig;

/// Range and range-rate noise of the new beacons, taken from the base scenario's beacons.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BeaconNoise {
    /// 1σ two-way range noise \[m\].
    pub range_sigma_m: f64,
    /// 1σ range-rate noise [m/s], if the template beacon had one.
    pub range_rate_sigma_mps: Option<f64>,
}

/// The noise of the first beacon of `cfg` with a range channel, preferring orbiters
/// (`orbiters = true`) or surface beacons. Errors when no beacon of the scenario has a range σ.
pub fn template_noise(cfg: &ScenarioConfig, orbiters: bool) -> Result<BeaconNoise, OptimizerError> {
    let pick = |b: &&BeaconConfig| {
        b.range_sigma_m().is_some() && matches!(b, BeaconConfig::Orbiter(_)) == orbiters
    };
    let b = cfg
        .beacons
        .iter()
        .find(pick)
        .or_else(|| cfg.beacons.iter().find(|b| b.range_sigma_m().is_some()))
        .ok_or_else(|| {
            OptimizerError::InvalidInput(format!(
                "scenario '{}' has no beacon with a range noise (range_sigma_m) to copy",
                cfg.name
            ))
        })?;
    if cfg.sensors.range.is_none() {
        return Err(OptimizerError::InvalidInput(format!(
            "scenario '{}' has no range sensor ([sensors.range]); the geometry objectives need \
             two-way range",
            cfg.name
        )));
    }
    Ok(BeaconNoise {
        range_sigma_m: b.range_sigma_m().unwrap_or(1.0),
        range_rate_sigma_mps: b.range_rate_sigma_mps(),
    })
}

/// Surface-beacon entries for `sites` (names `site-1`, `site-2`, …).
pub fn surface_beacons(sites: &[Site], noise: &BeaconNoise) -> Vec<BeaconConfig> {
    sites
        .iter()
        .enumerate()
        .map(|(i, s)| {
            let [lat, lon] = s.degrees();
            BeaconConfig::Surface(SurfaceBeaconConfig {
                name: format!("site-{}", i + 1),
                lat_deg: Some(lat),
                lon_deg: Some(lon),
                altitude_km: Some(s.altitude_m / 1e3),
                range_sigma_m: Some(noise.range_sigma_m),
                range_rate_sigma_mps: noise.range_rate_sigma_mps,
                ..Default::default()
            })
        })
        .collect()
}

/// Orbiter entries on circular orbits at `altitude_m` (names `orbiter-1`, …).
pub fn orbiter_beacons(
    elements: &[OrbitElements],
    altitude_m: f64,
    noise: &BeaconNoise,
) -> Vec<BeaconConfig> {
    elements
        .iter()
        .enumerate()
        .map(|(i, e)| {
            let [raan, inc, f] = e.canonical().degrees();
            BeaconConfig::Orbiter(OrbiterBeaconConfig {
                name: format!("orbiter-{}", i + 1),
                circular: Some(CircularConfig {
                    altitude_km: altitude_m / 1e3,
                    raan_deg: raan,
                    inc_deg: inc,
                    true_anomaly_deg: f,
                }),
                range_sigma_m: Some(noise.range_sigma_m),
                range_rate_sigma_mps: noise.range_rate_sigma_mps,
                ..Default::default()
            })
        })
        .collect()
}

/// `base` with its beacons replaced by `beacons`, renamed `name`, its description starting with
/// `note`; returned with its TOML text (a comment header, then the configuration), which has
/// been parsed back and validated.
pub fn with_beacons(
    base: &ScenarioConfig,
    beacons: Vec<BeaconConfig>,
    name: &str,
    note: &str,
) -> Result<(ScenarioConfig, String), OptimizerError> {
    let mut cfg = base.clone();
    cfg.beacons = beacons;
    cfg.name = name.to_string();
    cfg.description = format!(
        "{note} Otherwise as scenario '{}': {}",
        base.name,
        base.description.trim_end()
    );
    cfg.reference = format!("{}; beacon geometry by entrynav optimize", base.reference);
    cfg.validate()?;
    let text = format!(
        "# Written by `entrynav optimize` from scenario '{}'.\n# {note}\n{}",
        base.name,
        cfg.to_toml_string()
    );
    let parsed = ScenarioConfig::from_toml_str(&text, name)?;
    Ok((parsed, text))
}
