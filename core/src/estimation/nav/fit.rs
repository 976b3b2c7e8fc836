//! Whether a filter fits a scenario's onboard view ([`FilterKind::misfit`],
//! [`FilterKind::check_fits`]) and the checked filter list of a study
//! ([`FilterKind::parse_list`]).

use super::kind::{FilterKind, NavError};
use crate::dynamics::AugmentedParam;
use crate::estimation::adaptive::onboard_networks::load_network_set;
use crate::estimation::onboard::Onboard;
use crate::sensors::Channel;

impl FilterKind {
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
        if let Err(e) = load_network_set(onboard) {
            return Some(e.to_string());
        }
    }
    None
}
