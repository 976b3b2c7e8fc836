//! The same scenario with other beacons: what a placement study evaluates for every candidate.
//!
//! [`Scenario::with_beacons`] swaps `[[beacons]]` and rebuilds only what depends on them (the
//! beacons, their names, the channels, the ephemeris table, the faults and the onboard view),
//! keeping the atmospheres, vehicle, initial states and tuning already built — no file is read
//! again, so it works for scenarios whose atmospheres are tables.

use super::build::{Scenario, beacon_parts, channel_specs, ephemeris_table};
use super::error::ScenarioError;
use super::onboard::{OnboardParts, onboard_view};
use crate::beacons::BeaconConfig;
use std::sync::Arc;

impl Scenario {
    /// This scenario with `beacons` in place of its `[[beacons]]` (validated as a whole: a fault
    /// naming a beacon that is gone is an error naming the field). Equivalent to building the
    /// edited configuration from scratch.
    pub fn with_beacons(&self, beacons: Vec<BeaconConfig>) -> Result<Scenario, ScenarioError> {
        let mut config = self.config.clone();
        config.beacons = beacons;
        config.validate()?;
        let (built, beacon_names, faults) =
            beacon_parts(&config, &self.planet, self.truth_model.omega())?;
        let channels = channel_specs(&config, &beacon_names);
        let ephemerides = Arc::new(ephemeris_table(&config, &channels, &built));
        let old = &self.onboard;
        let mut onboard = onboard_view(OnboardParts {
            config: &config,
            model: old.model.clone(),
            climatology: old.climatology.clone(),
            measurement: self.measurement.clone(),
            channels: &channels,
            beacons: &built,
            beacon_names: &beacon_names,
            ephemerides: Arc::clone(&ephemerides),
            initial_bank: old.initial_bank,
            initial_estimate: old.initial_estimate.clone(),
        });
        onboard.density_networks = old.density_networks.clone();
        Ok(Scenario {
            config,
            planet: self.planet,
            truth_model: self.truth_model.clone(),
            truth_profiles: self.truth_profiles.clone(),
            truth_initial: self.truth_initial,
            truth_bank: self.truth_bank,
            onboard: Arc::new(onboard),
            beacons: built,
            beacon_names,
            ephemerides,
            measurement: self.measurement.clone(),
            channels,
            faults,
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::ScenarioConfig;

    /// Swapping beacons equals building the edited configuration: same channels, ephemerides
    /// and onboard view (compared through their debug text, which prints every field).
    #[test]
    fn equals_a_fresh_build() {
        let base = ScenarioConfig::builtin("ground-beacons-3").unwrap();
        let s = Scenario::build(base.clone(), &crate::files::no_files).unwrap();
        let mut edited = base.clone();
        edited.beacons.truncate(2);
        edited.beacons.reverse();
        let fresh = Scenario::build(edited.clone(), &crate::files::no_files).unwrap();
        let swapped = s.with_beacons(edited.beacons.clone()).unwrap();
        assert_eq!(format!("{:?}", swapped), format!("{:?}", fresh));
        assert_ne!(format!("{:?}", swapped), format!("{:?}", s));
    }

    /// A fault that names a removed beacon is refused, naming it.
    #[test]
    fn a_fault_on_a_removed_beacon_is_an_error() {
        let cfg = ScenarioConfig::builtin("four-beacon-fusion-faults").unwrap();
        let s = Scenario::build(cfg.clone(), &crate::files::no_files).unwrap();
        let kept = cfg.beacons[..2].to_vec();
        let err = s.with_beacons(kept).unwrap_err().to_string();
        assert!(err.contains("faults") && err.contains("orbiter-2"), "{err}");
    }
}
