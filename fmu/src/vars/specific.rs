//! The embedded scenario of a scenario-specific FMU ([`Specific`]) and the filter states its
//! outputs are named after ([`StateVar`]).

use entrynav::dynamics::AugmentedParam;
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::Scenario;
use std::sync::Arc;

/// A filter state of a specific FMU: its name (`r`, `lon`, `rho0`, …), unit and meaning.
#[derive(Debug, Clone, PartialEq)]
pub struct StateVar {
    /// Short name (the variable names are `est.<name>`, `est_sigma.<name>`, …).
    pub name: &'static str,
    /// Unit.
    pub unit: &'static str,
    /// Meaning.
    pub description: &'static str,
}

/// The embedded scenario of a specific FMU.
#[derive(Debug, Clone)]
pub struct Specific {
    /// Model identifier: `MarsEntryNav_<scenario name>`.
    pub identifier: String,
    /// The scenario, built from the file in `resources/`.
    pub scenario: Arc<Scenario>,
    /// Its file name in `resources/`.
    pub scenario_file: String,
    /// FNV-1a hash of the file's text (part of the GUID).
    pub toml_hash: u64,
    /// The default of the `filter` parameter.
    pub filter: FilterKind,
    /// The filter states, in state order.
    pub states: Vec<StateVar>,
}

pub(super) const SPHERICAL: [StateVar; 6] = [
    StateVar {
        name: "r",
        unit: "m",
        description: "radius",
    },
    StateVar {
        name: "lon",
        unit: "rad",
        description: "longitude",
    },
    StateVar {
        name: "lat",
        unit: "rad",
        description: "latitude",
    },
    StateVar {
        name: "v",
        unit: "m/s",
        description: "planet-relative speed",
    },
    StateVar {
        name: "fpa",
        unit: "rad",
        description: "flight-path angle",
    },
    StateVar {
        name: "heading",
        unit: "rad",
        description: "heading (north-clockwise)",
    },
];

pub(super) const CARTESIAN: [StateVar; 6] = [
    StateVar {
        name: "x",
        unit: "m",
        description: "inertial position x",
    },
    StateVar {
        name: "y",
        unit: "m",
        description: "inertial position y",
    },
    StateVar {
        name: "z",
        unit: "m",
        description: "inertial position z",
    },
    StateVar {
        name: "vx",
        unit: "m/s",
        description: "inertial velocity x",
    },
    StateVar {
        name: "vy",
        unit: "m/s",
        description: "inertial velocity y",
    },
    StateVar {
        name: "vz",
        unit: "m/s",
        description: "inertial velocity z",
    },
];

pub(super) fn augmented(a: AugmentedParam) -> StateVar {
    let (name, unit, description) = match a {
        AugmentedParam::Rho0 => (
            "rho0",
            "kg/m3",
            "reference density of the exponential model",
        ),
        AugmentedParam::LiftToDrag => ("lift_to_drag", "1", "lift-to-drag ratio"),
        AugmentedParam::CdSOverM => (
            "cd_s_over_m",
            "m2/kg",
            "drag coefficient times area over mass",
        ),
        AugmentedParam::DensityBias => ("density_bias", "1", "relative density bias"),
        AugmentedParam::AccelBiasX => ("accel_bias_x", "m/s2", "accelerometer bias, IMU axis x"),
        AugmentedParam::AccelBiasY => ("accel_bias_y", "m/s2", "accelerometer bias, IMU axis y"),
        AugmentedParam::AccelBiasZ => ("accel_bias_z", "m/s2", "accelerometer bias, IMU axis z"),
    };
    StateVar {
        name,
        unit,
        description,
    }
}

/// The identifier of the specific FMU of the scenario named `name`.
pub fn specific_identifier(name: &str) -> String {
    let tail: String = name
        .chars()
        .map(|c| if c.is_ascii_alphanumeric() { c } else { '_' })
        .collect();
    format!("MarsEntryNav_{tail}")
}
