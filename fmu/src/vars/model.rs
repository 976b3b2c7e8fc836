//! Which FMU an instance is: one of the five generic models ([`Model`]), or the combined model
//! specific to one embedded scenario ([`ModelSpec::for_scenario`]), whose state outputs carry the
//! scenario's state names and units.

use super::table::build;
use super::{Var, fnv1a64, table_guid};
use entrynav::dynamics::AugmentedParam;
use entrynav::estimation::nav::{FilterKind, NavError};
use entrynav::scenario::{Scenario, ScenarioConfig};
use std::sync::Arc;
use thiserror::Error;

/// The five generic FMUs.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Model {
    /// Entry dynamics, sensors and navigation filter (`MarsEntryNav`).
    Combined,
    /// The navigation filter alone, fed with measurements (`MarsEntryNavFilter`).
    Filter,
    /// Truth dynamics and sensors, producing the measurements (`MarsEntryTruth`).
    Truth,
    /// Entry guidance alone, fed with the navigation estimate and the accelerometer triad
    /// (`MarsEntryGuidance`): its output is the bank command.
    Guidance,
    /// Entry dynamics, sensors, navigation filter and guidance in one loop
    /// (`MarsEntryNavGuided`): guidance flies the filter's estimate, the truth flies its bank.
    Guided,
}

impl Model {
    /// All models.
    pub const ALL: [Model; 5] = [
        Model::Combined,
        Model::Filter,
        Model::Truth,
        Model::Guidance,
        Model::Guided,
    ];

    /// FMI model identifier (the shared library's file stem inside the `.fmu`).
    pub fn identifier(self) -> &'static str {
        match self {
            Model::Combined => "MarsEntryNav",
            Model::Filter => "MarsEntryNavFilter",
            Model::Truth => "MarsEntryTruth",
            Model::Guidance => "MarsEntryGuidance",
            Model::Guided => "MarsEntryNavGuided",
        }
    }

    /// One-line description.
    pub fn description(self) -> &'static str {
        match self {
            Model::Combined => {
                "Mars entry dynamics, sensors and navigation filter (entrynav), driven by a bank-angle command and beacon availability"
            }
            Model::Filter => {
                "Mars entry navigation filter (entrynav) alone, fed with accelerometer, air-data and radio measurements and their validity flags"
            }
            Model::Truth => {
                "Mars entry truth dynamics and sensors (entrynav): true trajectory and noisy measurements with validity flags"
            }
            Model::Guidance => {
                "Mars entry guidance (entrynav, the scenario's [guidance]): bank command through the rate and acceleration limits, from the navigation estimate and the accelerometer triad"
            }
            Model::Guided => {
                "Mars entry dynamics, sensors, navigation filter and guidance in one loop (entrynav, the scenario's [guidance]): guidance flies the filter's estimate, the truth flies the bank through the rate and acceleration limits, until the deployment trigger"
            }
        }
    }

    /// Whether this model runs the truth.
    pub fn has_truth(self) -> bool {
        matches!(self, Model::Combined | Model::Truth | Model::Guided)
    }

    /// Whether this model runs a filter.
    pub fn has_filter(self) -> bool {
        matches!(self, Model::Combined | Model::Filter | Model::Guided)
    }

    /// Whether the truth, the filter and their judgement run together (no measurement
    /// variables: the filter is fed inside).
    pub fn is_closed(self) -> bool {
        matches!(self, Model::Combined | Model::Guided)
    }

    /// The generic model whose GUID is `guid`.
    pub fn from_guid(guid: &str) -> Option<Model> {
        Model::ALL.into_iter().find(|m| super::guid_of(*m) == guid)
    }

    /// The generic model with identifier `id`.
    pub fn from_identifier(id: &str) -> Option<Model> {
        Model::ALL.into_iter().find(|m| m.identifier() == id)
    }
}

/// Why a scenario-specific model cannot be made.
#[derive(Debug, Error)]
pub enum SpecError {
    /// The filter does not fit the scenario.
    #[error(transparent)]
    Filter(#[from] NavError),
    /// More filter states than a table can name.
    #[error("the scenario's filter has {0} states; a specific FMU supports 6 to 12")]
    States(usize),
}

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

/// What an instance is: a generic model or a scenario-specific combined model, with its variable
/// table and GUID.
#[derive(Debug, Clone)]
pub struct ModelSpec {
    model: Model,
    specific: Option<Specific>,
    vars: Vec<Var>,
    guid: String,
}

const SPHERICAL: [StateVar; 6] = [
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

const CARTESIAN: [StateVar; 6] = [
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

fn augmented(a: AugmentedParam) -> StateVar {
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

impl ModelSpec {
    /// The generic `model`.
    pub fn generic(model: Model) -> ModelSpec {
        let vars = build(model, None);
        let guid = table_guid(model.identifier(), "", &vars);
        ModelSpec {
            model,
            specific: None,
            vars,
            guid,
        }
    }

    /// The combined model specific to `scenario` (read from `scenario_file` in `resources/`,
    /// whose text is `toml`), with `filter` as the default filter.
    pub fn for_scenario(
        scenario: Arc<Scenario>,
        scenario_file: &str,
        toml: &str,
        filter: FilterKind,
    ) -> Result<ModelSpec, SpecError> {
        filter.check_fits(&scenario.onboard)?;
        let fm = scenario.filter_model();
        let kin = if fm.kind.is_cartesian() {
            CARTESIAN
        } else {
            SPHERICAL
        };
        let states: Vec<StateVar> = kin
            .into_iter()
            .chain(fm.augmented.iter().map(|a| augmented(*a)))
            .collect();
        if !(6..=12).contains(&states.len()) {
            return Err(SpecError::States(states.len()));
        }
        let specific = Specific {
            identifier: specific_identifier(&scenario.config.name),
            scenario,
            scenario_file: scenario_file.to_string(),
            toml_hash: fnv1a64(toml.as_bytes(), 0),
            filter,
            states,
        };
        let vars = build(Model::Combined, Some(&specific));
        let extra = format!(
            "{}|{:016x}|{}",
            specific.scenario_file,
            specific.toml_hash,
            filter.name()
        );
        let guid = table_guid(&specific.identifier, &extra, &vars);
        Ok(ModelSpec {
            model: Model::Combined,
            specific: Some(specific),
            vars,
            guid,
        })
    }

    /// The generic model, or the base of a specific one.
    pub fn model(&self) -> Model {
        self.model
    }

    /// The embedded scenario of a specific model.
    pub fn specific(&self) -> Option<&Specific> {
        self.specific.as_ref()
    }

    /// The model identifier.
    pub fn identifier(&self) -> &str {
        match &self.specific {
            Some(s) => &s.identifier,
            None => self.model.identifier(),
        }
    }

    /// One-line description.
    pub fn description(&self) -> String {
        match &self.specific {
            Some(s) => format!(
                "{} for scenario '{}' (embedded in resources/{}; state outputs named after its states)",
                self.model.description(),
                s.scenario.config.name,
                s.scenario_file
            ),
            None => self.model.description().to_string(),
        }
    }

    /// The variables, in value-reference order.
    pub fn vars(&self) -> &[Var] {
        &self.vars
    }

    /// The GUID.
    pub fn guid(&self) -> &str {
        &self.guid
    }

    /// Start time, stop time and step size of the default experiment: the scenario's duration
    /// (the default scenario's for a generic model) with one step per fastest sensor sample; for
    /// the guidance FMU, the guided scenario's duration with one step per guidance period (one
    /// cycle per step, each with the estimate given at its start); for the guided FMU, the same
    /// (its steps are whole truth steps, and a guidance period is).
    pub fn default_experiment(&self) -> (f64, f64, f64) {
        if matches!(self.model, Model::Guidance | Model::Guided) {
            // The guided scenario builds with [guidance] (tested), so the fallback is never taken.
            return guided_scenario()
                .ok()
                .and_then(|s| {
                    let g = s.config.guidance.as_ref()?;
                    Some((0.0, s.config.timing.duration_s, g.period_s()))
                })
                .unwrap_or((0.0, 1.0, 1.0));
        }
        let timing = |s: &Scenario| {
            let step = s
                .channels
                .iter()
                .map(|c| c.period_s)
                .min_by(|a, b| a.total_cmp(b))
                .unwrap_or(s.config.timing.truth_step_s);
            (0.0, s.config.timing.duration_s, step)
        };
        match &self.specific {
            Some(s) => timing(&s.scenario),
            // The default scenario is a built-in (tested), so the fallback is never taken.
            None => ScenarioConfig::builtin(super::DEFAULT_SCENARIO)
                .and_then(|cfg| Scenario::build(cfg, &entrynav::files::no_files))
                .map(|s| timing(&s))
                .unwrap_or((0.0, 1.0, 1.0)),
        }
    }
}

/// The scenario of [`super::GUIDED_SCENARIO_FILE`] (it refers to no other file).
pub fn guided_scenario() -> Result<Scenario, entrynav::scenario::ScenarioError> {
    let cfg =
        ScenarioConfig::from_toml_str(&super::guided_scenario_toml(), super::GUIDED_SCENARIO_FILE)?;
    Scenario::build(cfg, &entrynav::files::no_files)
}
