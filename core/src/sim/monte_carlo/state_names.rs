//! [`state_names`]: the names of a scenario's filter states, the columns of every study's
//! tables.

use crate::scenario::Scenario;

/// State names of a scenario's filter model.
pub fn state_names(scenario: &Scenario) -> Vec<String> {
    let fm = scenario.filter_model();
    let kin: [&str; 6] = if fm.kind.is_cartesian() {
        ["x_m", "y_m", "z_m", "vx_mps", "vy_mps", "vz_mps"]
    } else {
        [
            "r_m",
            "lon_rad",
            "lat_rad",
            "v_mps",
            "fpa_rad",
            "heading_rad",
        ]
    };
    kin.iter()
        .map(|s| s.to_string())
        .chain(fm.augmented.iter().map(|a| a.name().to_string()))
        .collect()
}
