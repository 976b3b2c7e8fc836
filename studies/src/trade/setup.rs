//! What every trade mode starts from: the built scenario with what its truth table says
//! ([`TradeScenario`]), then the checked truth profiles, the filters and the run count
//! ([`TradeSetup`]).

use crate::error::StudyResult;
use crate::options::{MAX_RUNS, check_count};
use crate::provenance::Provenance;
use crate::scenario::input::ScenarioInput;
use crate::scenario::truth_atmosphere::{check_profile_covers, truth_table_notes};
use crate::trade::options::TradeOptions;
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::Scenario;
use std::path::PathBuf;

/// A trade's scenario, built, with the warnings and notes of its truth table (each without its
/// `warning: ` / `note: ` prefix) for the front end to show before the work starts.
pub struct TradeScenario {
    /// The runnable scenario.
    pub scenario: Scenario,
    /// The `--set` overrides it was built with (for provenance).
    pub overrides: Vec<String>,
    /// The truth atmosphere file that replaced the scenario's, if any.
    pub atmosphere_file: Option<PathBuf>,
    /// What the truth table assumed about its heights.
    pub warnings: Vec<String>,
    /// How the runs fly a table of several profiles.
    pub notes: Vec<String>,
}

impl TradeScenario {
    /// Build `input` (overrides and truth atmosphere already applied).
    pub fn build(input: &ScenarioInput) -> StudyResult<TradeScenario> {
        let scenario = input.build()?;
        let (warnings, notes) = truth_table_notes(&scenario);
        Ok(TradeScenario {
            scenario,
            overrides: input.overrides.clone(),
            atmosphere_file: input.atmosphere_file.clone(),
            warnings,
            notes,
        })
    }
}

/// The scenario, filters and run count of a trade.
pub struct TradeSetup {
    /// The runnable scenario.
    pub scenario: Scenario,
    /// The `--set` overrides it was built with.
    pub overrides: Vec<String>,
    /// The truth atmosphere file that replaced the scenario's, if any.
    pub atmosphere_file: Option<PathBuf>,
    /// The filters, each checked to fit the scenario.
    pub filters: Vec<FilterKind>,
    /// Monte Carlo runs: `options.runs`, else the scenario's.
    pub runs: usize,
}

impl TradeSetup {
    /// Check that every truth profile covers the nominal trajectory, parse the filters (each
    /// must fit the scenario) and settle the run count.
    pub fn new(built: TradeScenario, options: &TradeOptions) -> StudyResult<TradeSetup> {
        let TradeScenario {
            scenario,
            overrides,
            atmosphere_file,
            ..
        } = built;
        if let Some(file) = &atmosphere_file {
            check_profile_covers(&scenario, file)?;
        }
        let filters =
            crate::filters::fitting_filters("filters", &options.filters, &scenario.onboard)?;
        let runs = options.runs.unwrap_or(scenario.config.monte_carlo.runs);
        check_count("runs", runs, 1, MAX_RUNS)?;
        Ok(TradeSetup {
            scenario,
            overrides,
            atmosphere_file,
            filters,
            runs,
        })
    }

    /// The provenance of this trade run by `command_line` (program name first).
    pub fn provenance(&self, command_line: Vec<String>) -> Provenance {
        Provenance::new(command_line, &self.overrides)
            .with_scenario(&self.scenario, self.atmosphere_file.as_deref())
    }

    /// The label of its progress: `scenario × filters`.
    pub fn label(&self, options: &TradeOptions) -> String {
        format!("{} × {}", self.scenario.config.name, options.filters)
    }
}
