//! Filter names and whether a filter fits a scenario.

use crate::scenario::Scenario;
use thiserror::Error;

/// Why a filter cannot be used as asked.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum NavError {
    /// Unknown filter name.
    #[error("unknown filter '{name}'; valid filters are: {valid}")]
    UnknownFilter {
        /// What was asked for.
        name: String,
        /// Comma-separated valid names.
        valid: String,
    },
    /// The filter needs something the scenario does not have.
    #[error(
        "filter '{filter}' does not fit scenario '{scenario}': {reason}; filters that fit: {fits}"
    )]
    DoesNotFit {
        /// Filter name.
        filter: String,
        /// Scenario name.
        scenario: String,
        /// What is missing.
        reason: String,
        /// Filters that do fit this scenario.
        fits: String,
    },
    /// The filter state dimension is not supported.
    #[error("filter state dimension {0} is not supported (supported: 6 to 10)")]
    Dimension(usize),
}

/// The navigation filters available to trade studies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FilterKind {
    /// Centralised EKF over every channel (seed 000 eq. 17–18).
    Ekf,
    /// Centralised UKF (seed 001 eq. 41–66 without consider states).
    Ukf,
    /// One local EKF per beacon (IMU + that beacon), fused by covariance intersection with
    /// determinant-optimal weights, without feedback (seed 000 §3.3).
    Ci,
    /// Distributed CI fusion with information feedback and fast ∞-norm weights (seed 000 §3.4).
    Dcifaif,
    /// Classical multiple-model bank over density biases (Magill posterior probabilities).
    Mmae,
    /// Seed 003's modified mixture-of-experts bank with measurement normalisation (eq. 17–25).
    MmaeMoe,
}

impl FilterKind {
    /// All filters, in listing order.
    pub const ALL: [FilterKind; 6] = [
        FilterKind::Ekf,
        FilterKind::Ukf,
        FilterKind::Ci,
        FilterKind::Dcifaif,
        FilterKind::Mmae,
        FilterKind::MmaeMoe,
    ];

    /// The name used on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            FilterKind::Ekf => "ekf",
            FilterKind::Ukf => "ukf",
            FilterKind::Ci => "ci",
            FilterKind::Dcifaif => "dcifaif",
            FilterKind::Mmae => "mmae",
            FilterKind::MmaeMoe => "mmae-moe",
        }
    }

    /// Parse a filter name.
    pub fn parse(name: &str) -> Result<FilterKind, NavError> {
        FilterKind::ALL
            .into_iter()
            .find(|k| k.name() == name.trim())
            .ok_or_else(|| NavError::UnknownFilter {
                name: name.to_string(),
                valid: FilterKind::ALL.map(|k| k.name()).join(", "),
            })
    }

    /// Why this filter cannot run on `scenario`, if it cannot.
    pub fn misfit(self, scenario: &Scenario) -> Option<String> {
        let radio_beacons = (0..scenario.beacons.len())
            .filter(|&i| {
                scenario
                    .channels
                    .iter()
                    .any(|c| c.channel.beacon() == Some(i))
            })
            .count();
        match self {
            FilterKind::Ci | FilterKind::Dcifaif if radio_beacons < 2 => Some(format!(
                "it fuses one local filter per radio beacon and needs at least 2 beacons with radio measurements (the scenario has {radio_beacons})"
            )),
            FilterKind::Mmae | FilterKind::MmaeMoe if scenario.config.filter.model_bank_density_bias.len() < 2 => Some(
                "it needs a model bank: set filter.model_bank_density_bias to at least two density biases".to_string(),
            ),
            _ => None,
        }
    }

    /// Check that the filter fits `scenario`, with an error listing the filters that do.
    pub fn check_fits(self, scenario: &Scenario) -> Result<(), NavError> {
        match self.misfit(scenario) {
            None => Ok(()),
            Some(reason) => Err(NavError::DoesNotFit {
                filter: self.name().to_string(),
                scenario: scenario.config.name.clone(),
                reason,
                fits: FilterKind::ALL
                    .iter()
                    .filter(|k| k.misfit(scenario).is_none())
                    .map(|k| k.name())
                    .collect::<Vec<_>>()
                    .join(", "),
            }),
        }
    }

    /// Parse a comma-separated list and check every filter fits the scenario.
    pub fn parse_list(list: &str, scenario: &Scenario) -> Result<Vec<FilterKind>, NavError> {
        let mut out = Vec::new();
        for name in list.split(',').filter(|s| !s.trim().is_empty()) {
            let k = FilterKind::parse(name)?;
            k.check_fits(scenario)?;
            if !out.contains(&k) {
                out.push(k);
            }
        }
        if out.is_empty() {
            return Err(NavError::UnknownFilter {
                name: list.to_string(),
                valid: FilterKind::ALL.map(|k| k.name()).join(", "),
            });
        }
        Ok(out)
    }
}
