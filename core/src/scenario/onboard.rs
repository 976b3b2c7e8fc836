//! The onboard view of a scenario: the [`Onboard`] value every navigation filter is built from.
//!
//! This is where the scenario decides what the vehicle knows: the filter's own dynamics,
//! atmosphere and vehicle constants, the channels with the noise the filter *assumes*
//! (`filter.imu_sigma_mps2` may differ from the sensor's), the beacons' ephemerides, the filter
//! step, the tuning and the nominal initial estimate. The truth model, the dispersions, the
//! sensor biases and the true noise stay out.

use super::config::ScenarioConfig;
use crate::atmosphere::AtmosphereModel;
use crate::beacons::{Beacon, EphemerisTable};
use crate::dynamics::EntryModel;
use crate::estimation::nav::FilterKind;
use crate::estimation::ukf::UkfParams;
use crate::estimation::{FilterRetune, FilterTuning, Onboard, OnboardChannel};
use crate::sensors::ChannelSpec;
use crate::sensors::MeasurementModel;
use std::sync::Arc;

/// What [`onboard_view`] is built from (the pieces of a scenario being built).
pub(super) struct OnboardParts<'a> {
    pub config: &'a ScenarioConfig,
    pub model: EntryModel<AtmosphereModel>,
    pub climatology: AtmosphereModel,
    pub measurement: MeasurementModel,
    pub channels: &'a [ChannelSpec],
    pub beacons: &'a [Beacon],
    pub beacon_names: &'a [String],
    pub ephemerides: Arc<EphemerisTable>,
    pub initial_bank: f64,
    pub initial_estimate: Vec<f64>,
}

/// The onboard view of a scenario being built.
pub(super) fn onboard_view(p: OnboardParts<'_>) -> Onboard {
    let f = &p.config.filter;
    Onboard {
        scenario_name: p.config.name.clone(),
        model: p.model,
        climatology: p.climatology,
        measurement: p.measurement,
        channels: p
            .channels
            .iter()
            .map(|c| OnboardChannel {
                channel: c.channel,
                name: c.name.clone(),
                noise: c.filter_noise,
            })
            .collect(),
        beacons: p.beacons.to_vec(),
        beacon_names: p.beacon_names.to_vec(),
        ephemerides: p.ephemerides,
        filter_step_s: p.config.timing.filter_step_s,
        initial_bank: p.initial_bank,
        initial_estimate: p.initial_estimate,
        density_networks: None,
        tuning: FilterTuning {
            p0_diag: f.p0_diag.clone(),
            q_diag: f.q_diag.clone(),
            process_noise: f.process_noise,
            n_consider: f.consider.len(),
            update_iterations: f.update_iterations,
            ukf: UkfParams::new(f.ukf.alpha, f.ukf.beta, f.ukf.kappa),
            model_bank_density_bias: f.model_bank_density_bias.clone(),
            fusion_covariance: f.fusion_covariance,
            density: f.density.clone(),
            gating: f.gating,
        },
        per_filter: per_filter_tuning(p.config, p.channels),
    }
}

/// `[filter.tuned.<name>]` as onboard re-tunings: the filter's Q (or the shared one) and, per
/// channel, its noise factor relative to the shared `filter.noise_inflation`. Names are checked
/// by validation; an unknown one is skipped here.
fn per_filter_tuning(config: &ScenarioConfig, channels: &[ChannelSpec]) -> Vec<FilterRetune> {
    let f = &config.filter;
    let shared = f.noise_inflation.unwrap_or_default();
    f.tuned
        .iter()
        .filter_map(|(name, t)| {
            let kind = FilterKind::parse(name).ok()?;
            let noise_factor = channels
                .iter()
                .map(|c| match &t.noise_inflation {
                    Some(own) => own.factor(c.channel) / shared.factor(c.channel),
                    None => 1.0,
                })
                .collect();
            Some(FilterRetune {
                kind,
                q_diag: t.q_diag.clone().unwrap_or_else(|| f.q_diag.clone()),
                process_noise: t.process_noise.unwrap_or(f.process_noise),
                noise_factor,
            })
        })
        .collect()
}
