//! Human names and units for the report's code names (`lon_rad` → "longitude", "rad"), and the
//! names of the fusion weights and model probabilities (beacons, bank members).

/// (quantity, unit) of a state or metric name with an SI suffix.
pub fn quantity(name: &str) -> (String, &'static str) {
    let fixed = match name {
        "r_m" => Some(("radius", "m")),
        "lon_rad" => Some(("longitude", "rad")),
        "lat_rad" => Some(("latitude", "rad")),
        "v_mps" => Some(("speed", "m/s")),
        "fpa_rad" => Some(("flight-path angle", "rad")),
        "heading_rad" => Some(("heading", "rad")),
        "pos_m" => Some(("position", "m")),
        "vel_mps" => Some(("velocity", "m/s")),
        "downrange_m" => Some(("downrange position", "m")),
        "crossrange_m" => Some(("crossrange position", "m")),
        "up_m" => Some(("up (radial) position", "m")),
        "rho0_kgm3" => Some(("reference density ρ0", "kg/m³")),
        "lift_to_drag" => Some(("lift-to-drag ratio", "1")),
        "density_bias" => Some(("density bias", "1")),
        "cd_s_over_m_m2kg" => Some(("CdS/m", "m²/kg")),
        _ => None,
    };
    if let Some((q, u)) = fixed {
        return (q.to_string(), u);
    }
    for (suffix, unit) in [
        ("_mps2", "m/s²"),
        ("_mps", "m/s"),
        ("_rad", "rad"),
        ("_kgm3", "kg/m³"),
        ("_m", "m"),
        ("_s", "s"),
    ] {
        if let Some(stem) = name.strip_suffix(suffix) {
            let stem = stem
                .replace("accel_bias", "accelerometer bias")
                .replace('_', " ");
            // x_m → "x position", vx_mps → "vx velocity"
            let what = match unit {
                "m" if stem.len() == 1 => format!("{stem} position"),
                "m/s" if stem.len() == 2 && stem.starts_with('v') => {
                    format!("{} velocity", &stem[1..])
                }
                _ => stem,
            };
            return (what, unit);
        }
    }
    (name.replace('_', " "), "1")
}

/// An axis label: `quantity what (unit)`, e.g. `longitude error RMSE (rad)`.
pub fn axis(name: &str, what: &str) -> String {
    let (q, u) = quantity(name);
    format!("{q} {what} ({u})")
}

/// What the weights of each filter are called.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct WeightNames {
    /// Names of the beacons with radio channels, in the fusion's local-filter order.
    pub radio_beacons: Vec<String>,
    /// Density biases of the MMAE model bank, in bank order.
    pub model_bank: Vec<f64>,
}

impl WeightNames {
    /// From the scenario: its radio beacons and model bank.
    pub fn of_scenario(scenario: &entrynav::scenario::Scenario) -> WeightNames {
        let o = &scenario.onboard;
        WeightNames {
            radio_beacons: o
                .radio_beacons()
                .into_iter()
                .map(|b| {
                    o.beacon_names
                        .get(b)
                        .cloned()
                        .unwrap_or(format!("beacon {b}"))
                })
                .collect(),
            model_bank: o.tuning.model_bank_density_bias.clone(),
        }
    }

    /// From the report's channel names alone (`range_NAME_m`, `range_rate_NAME_mps`), for a
    /// study merged from shards.
    pub fn of_channels(channels: &[String]) -> WeightNames {
        let mut radio_beacons: Vec<String> = Vec::new();
        for c in channels {
            let name = c
                .strip_prefix("range_rate_")
                .and_then(|s| s.strip_suffix("_mps"))
                .or_else(|| c.strip_prefix("range_").and_then(|s| s.strip_suffix("_m")));
            if let Some(n) = name.filter(|n| !radio_beacons.iter().any(|b| b == n)) {
                radio_beacons.push(n.to_string());
            }
        }
        WeightNames {
            radio_beacons,
            model_bank: Vec::new(),
        }
    }

    /// Labels of the `n` weights of filter `filter`, and what they are.
    pub fn labels(&self, filter: &str, n: usize) -> (Vec<String>, &'static str) {
        let pick = |names: Vec<String>, what| {
            if names.len() == n {
                (names, what)
            } else {
                ((0..n).map(|j| format!("weight {j}")).collect(), "weight")
            }
        };
        match filter {
            "ci" | "dcifaif" => pick(self.radio_beacons.clone(), "fusion weight"),
            "mmae" | "mmae-moe" => pick(
                self.model_bank
                    .iter()
                    .map(|b| format!("density bias {:+.1} %", 100.0 * b))
                    .collect(),
                "model probability",
            ),
            _ => pick(Vec::new(), "weight"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn code_names_become_quantities_with_units() {
        assert_eq!(axis("lon_rad", "error RMSE"), "longitude error RMSE (rad)");
        assert_eq!(axis("pos_m", "error RMSE"), "position error RMSE (m)");
        assert_eq!(quantity("accel_bias_x_mps2").1, "m/s²");
        assert_eq!(quantity("x_m").0, "x position");
        assert_eq!(quantity("vz_mps").0, "z velocity");
    }

    #[test]
    fn beacon_names_from_channels_in_order() {
        let ch: Vec<String> = [
            "accel_x_mps2",
            "range_s-1_m",
            "range_o_2_m",
            "range_rate_s-1_mps",
        ]
        .map(String::from)
        .to_vec();
        let w = WeightNames::of_channels(&ch);
        assert_eq!(w.radio_beacons, ["s-1", "o_2"]);
        assert_eq!(w.labels("dcifaif", 2).0, ["s-1", "o_2"]);
        assert_eq!(w.labels("dcifaif", 3).0[2], "weight 2");
    }
}
