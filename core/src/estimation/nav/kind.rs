//! Filter names and whether a filter fits a scenario.

use crate::estimation::Onboard;
use crate::state_dim::UnsupportedDimension;
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
    #[error(transparent)]
    Dimension(#[from] UnsupportedDimension),
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
    /// UKF with Myers–Tapley process-noise covariance matching (seed 001 eq. 20–21, batch 10).
    UkfCm,
    /// UKF with an augmented density correction factor 𝒦 (seed 001 eq. 24–26, random walk).
    UkfAc,
    /// Unscented Schmidt–Kalman filter with an online-adapted density network (seed 001 §IV).
    UskfNn,
}

impl FilterKind {
    /// All filters, in listing order.
    pub const ALL: [FilterKind; 9] = [
        FilterKind::Ekf,
        FilterKind::Ukf,
        FilterKind::Ci,
        FilterKind::Dcifaif,
        FilterKind::Mmae,
        FilterKind::MmaeMoe,
        FilterKind::UkfCm,
        FilterKind::UkfAc,
        FilterKind::UskfNn,
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
            FilterKind::UkfCm => "ukf-cm",
            FilterKind::UkfAc => "ukf-ac",
            FilterKind::UskfNn => "uskf-nn",
        }
    }

    /// Parse a filter name (the one parser of filter names; [`FromStr`](std::str::FromStr) calls it).
    pub fn parse(name: &str) -> Result<FilterKind, NavError> {
        FilterKind::ALL
            .into_iter()
            .find(|k| k.name() == name.trim())
            .ok_or_else(|| NavError::UnknownFilter {
                name: name.to_string(),
                valid: FilterKind::ALL.map(|k| k.name()).join(", "),
            })
    }

    /// Why this filter cannot run on the `onboard` configuration, if it cannot.
    pub fn misfit(self, onboard: &Onboard) -> Option<String> {
        let radio_beacons = onboard.radio_beacons().len();
        match self {
            FilterKind::Ci | FilterKind::Dcifaif if radio_beacons < 2 => Some(format!(
                "it fuses one local filter per radio beacon and needs at least 2 beacons with radio measurements (the scenario has {radio_beacons})"
            )),
            FilterKind::Mmae | FilterKind::MmaeMoe if onboard.tuning.model_bank_density_bias.len() < 2 => Some(
                "it needs a model bank: set filter.model_bank_density_bias to at least two density biases".to_string(),
            ),
            FilterKind::UkfAc | FilterKind::UskfNn => density_filter_misfit(self, onboard),
            _ => None,
        }
    }

    /// Check that the filter fits the `onboard` configuration, with an error listing the filters
    /// that do.
    pub fn check_fits(self, onboard: &Onboard) -> Result<(), NavError> {
        match self.misfit(onboard) {
            None => Ok(()),
            Some(reason) => Err(NavError::DoesNotFit {
                filter: self.name().to_string(),
                scenario: onboard.scenario_name.clone(),
                reason,
                fits: FilterKind::ALL
                    .iter()
                    .filter(|k| k.misfit(onboard).is_none())
                    .map(|k| k.name())
                    .collect::<Vec<_>>()
                    .join(", "),
            }),
        }
    }

    /// Parse a comma-separated list and check every filter fits the `onboard` configuration.
    pub fn parse_list(list: &str, onboard: &Onboard) -> Result<Vec<FilterKind>, NavError> {
        let mut out = Vec::new();
        for name in list.split(',').filter(|s| !s.trim().is_empty()) {
            let k = FilterKind::parse(name)?;
            k.check_fits(onboard)?;
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

/// Why UKF-AC or USKF-NN (seed 001's 8-state layout plus one internal density state) cannot run
/// on the `onboard` configuration.
fn density_filter_misfit(kind: FilterKind, onboard: &Onboard) -> Option<String> {
    use crate::dynamics::AugmentedParam;
    use crate::sensors::Channel;
    let augment = &onboard.model.augmented;
    if onboard.model.kind.is_cartesian() {
        return Some(
            "it needs the spherical state [r, lon, lat, v, fpa, heading, CdS/m, L/D] (filter.dynamics = \"spherical\")"
                .to_string(),
        );
    }
    let layout = augment.len() == 2
        && augment.contains(&AugmentedParam::CdSOverM)
        && augment.contains(&AugmentedParam::LiftToDrag);
    if !layout {
        let names: Vec<String> = augment
            .iter()
            .map(|a| format!("\"{}\"", a.config_name()))
            .collect();
        return Some(format!(
            "it needs the 8-state layout of seed 001 with filter.augment = [\"cd-s-over-m\", \"lift-to-drag\"] (the scenario has [{}])",
            names.join(", ")
        ));
    }
    if onboard.tuning.n_consider > 0 {
        return Some(
            "it estimates its own density state and supports no consider parameters (remove filter.consider)"
                .to_string(),
        );
    }
    let density_sensor = onboard.channels.iter().any(|c| {
        matches!(
            c.channel,
            Channel::Accel(_) | Channel::DynamicPressure | Channel::Heating
        )
    });
    if !density_sensor {
        return Some(
            "it needs a density-sensitive sensor (accelerometer, dynamic pressure or heating)"
                .to_string(),
        );
    }
    if kind == FilterKind::UskfNn {
        if onboard.tuning.density.is_none() {
            return Some(
                "it needs a [filter.density] section naming a trained network (see `entrynav train-density`)"
                    .to_string(),
            );
        }
        if let Err(e) = crate::estimation::adaptive::load_network_set(onboard) {
            return Some(e.to_string());
        }
    }
    None
}

impl std::str::FromStr for FilterKind {
    type Err = NavError;

    fn from_str(name: &str) -> Result<FilterKind, NavError> {
        FilterKind::parse(name)
    }
}

impl std::fmt::Display for FilterKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}
