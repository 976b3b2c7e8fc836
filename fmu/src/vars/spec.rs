//! What an instance is ([`ModelSpec`]): a generic model or the combined model specific to one
//! embedded scenario ([`ModelSpec::for_scenario`]), whose state outputs carry the scenario's state
//! names and units; with its variable table and GUID.

use super::defaults::DEFAULT_SCENARIO;
use super::guid::{fnv1a64, table_guid};
use super::model::Model;
use super::specific::{CARTESIAN, SPHERICAL, Specific, StateVar, augmented, specific_identifier};
use super::table::guidance::guided_scenario;
use super::table::{build, variables};
use super::var::Var;
use entrynav::estimation::nav::{FilterKind, NavError};
use entrynav::scenario::{Scenario, ScenarioConfig};
use std::sync::Arc;
use thiserror::Error;

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

/// What an instance is: a generic model or a scenario-specific combined model, with its variable
/// table and GUID.
#[derive(Debug, Clone)]
pub struct ModelSpec {
    model: Model,
    specific: Option<Specific>,
    vars: Vec<Var>,
    guid: String,
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
            None => ScenarioConfig::builtin(DEFAULT_SCENARIO)
                .and_then(|cfg| Scenario::build(cfg, &entrynav::files::no_files))
                .map(|s| timing(&s))
                .unwrap_or((0.0, 1.0, 1.0)),
        }
    }
}

impl Model {
    /// The generic model whose GUID is `guid`.
    pub fn from_guid(guid: &str) -> Option<Model> {
        Model::ALL.into_iter().find(|m| guid_of(*m) == guid)
    }
}

/// The GUID of the generic `model`.
pub fn guid_of(model: Model) -> String {
    table_guid(model.identifier(), "", &variables(model))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::vars::units::UNITS;
    use crate::vars::var::Type;
    use entrynav::scenario::ScenarioConfig;
    use std::collections::HashSet;

    #[test]
    fn names_and_refs_unique_guids_distinct() {
        let mut guids = HashSet::new();
        for m in Model::ALL {
            let vars = variables(m);
            let names: HashSet<_> = vars.iter().map(|v| v.name.clone()).collect();
            assert_eq!(names.len(), vars.len());
            for (i, v) in vars.iter().enumerate() {
                assert_eq!(v.vr as usize, i);
                assert_eq!(v.settable(), v.start.is_some(), "{}", v.name);
                assert!(v.declared.is_none() || v.ty == Type::Integer, "{}", v.name);
                if let Some(u) = v.unit {
                    assert!(UNITS.iter().any(|d| d.0 == u), "{}: unit {u}", v.name);
                }
            }
            assert!(guids.insert(guid_of(m)));
            assert_eq!(Model::from_guid(&guid_of(m)), Some(m));
            assert_eq!(ModelSpec::generic(m).guid(), guid_of(m));
        }
        assert_eq!(Model::from_guid("{nope}"), None);
    }

    #[test]
    fn the_guided_scenario_builds_with_guidance_and_an_accelerometer_triad() {
        let s = guided_scenario().unwrap();
        assert_eq!(s.config.name, "msl-guided");
        assert!(s.build_guidance().unwrap().is_ok());
        let (_, stop, step) = ModelSpec::generic(Model::Guidance).default_experiment();
        let period = s.config.guidance.as_ref().unwrap().period_s();
        assert_eq!((stop, step), (s.config.timing.duration_s, period));
        // Without the section (and with msl-airdata's name, description and constant bank) it
        // is msl-airdata again, but for its MSL-class aerodynamic dispersions and the filter
        // prior that matches them (issue 50), and for USKF-NN's density adaptation: msl-guided
        // has no level-and-slope correction, so its consider parameter stays at 3 % (issue 49).
        let base = ScenarioConfig::builtin("msl-airdata").unwrap();
        let mut cfg = s.config.clone();
        cfg.guidance = None;
        cfg.name = base.name.clone();
        cfg.description = base.description.clone();
        cfg.truth.bank_deg = base.truth.bank_deg;
        assert_eq!(
            (
                cfg.dispersions.cd_s_over_m_m2kg,
                cfg.dispersions.lift_to_drag
            ),
            (2.34e-4, 1.0e-2)
        );
        assert_eq!(
            (cfg.filter.p0_diag[6], cfg.filter.p0_diag[7]),
            (5.4756e-8, 1.0e-4)
        );
        cfg.dispersions.cd_s_over_m_m2kg = base.dispersions.cd_s_over_m_m2kg;
        cfg.dispersions.lift_to_drag = base.dispersions.lift_to_drag;
        cfg.filter.p0_diag = base.filter.p0_diag.clone();
        let slope = |c: &ScenarioConfig| c.filter.density.as_ref().and_then(|d| d.slope_window);
        assert_eq!((slope(&cfg), slope(&base)), (None, Some(2)));
        let pss = |c: &ScenarioConfig| c.filter.density.as_ref().unwrap().consider_pss;
        assert_eq!((pss(&cfg), pss(&base)), (1e-3, 1e-4));
        // Only those three fields differ: everything else in the density section must match.
        let (d, b) = (
            cfg.filter.density.as_mut().unwrap(),
            base.filter.density.as_ref().unwrap(),
        );
        d.slope_window = b.slope_window;
        d.consider_pss = b.consider_pss;
        d.consider_p0 = b.consider_p0;
        assert_eq!(cfg.to_toml_string(), base.to_toml_string());
    }
}
