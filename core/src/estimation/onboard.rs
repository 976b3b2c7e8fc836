//! [`Onboard`]: what the vehicle knows onboard — the only thing a navigation filter is built from.
//!
//! A filter holds an `Arc<Onboard>` and nothing else from the scenario: its own dynamics and
//! atmosphere model, the deterministic measurement model, the channels with the noise it
//! *assumes*, the beacon ephemerides, its timing and tuning, and the commanded bank at the start.
//! It cannot reach the truth model, the truth's dispersions, the sensor biases and true noise, or
//! the raw scenario configuration: those stay in the scenario and the simulation engine, which is
//! where a filter is judged against the truth.
//!
//! The scenario layer builds the value (`Scenario::build`); the estimation layer never imports
//! the scenario or the simulation.

use super::adaptive::config::DensityFilterConfig;
use super::adaptive::network::DensityNetworkSet;
use super::nav::kind::FilterKind;
use super::process_noise::ProcessNoiseModel;
use super::unscented::UkfParams;
use crate::atmosphere::AtmosphereModel;
use crate::beacons::{Beacon, BeaconState, EphemerisTable};
use crate::dynamics::EntryModel;
use crate::sensors::{Channel, MeasurementModel, Noise};
use std::borrow::Cow;
use std::sync::Arc;

/// One measurement channel as the filter sees it: what it measures and the noise the filter
/// assumes (which may differ from the sensor's true noise). Slot `c` of a
/// [`MeasurementEpoch`](crate::sensors::MeasurementEpoch) is channel `c` of [`Onboard::channels`].
#[derive(Debug, Clone, PartialEq)]
pub struct OnboardChannel {
    /// What is measured.
    pub channel: Channel,
    /// Column name (SI unit suffix).
    pub name: String,
    /// Noise 1σ the filter assumes.
    pub noise: Noise,
}

/// How DCIFAIF's fused covariance is formed and fed back (`filter.fusion_covariance`).
#[derive(
    Debug,
    Clone,
    Copy,
    PartialEq,
    Eq,
    Default,
    serde::Serialize,
    serde::Deserialize,
    schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum FusionCovariance {
    /// The exact covariance of the CI-weighted estimate, fed back to every local filter
    /// (`nav::fusion_exact`).
    #[default]
    Exact,
    /// Seed 000 as printed: the CI bound (eq. 20), fed back as P_CI/ω_i (eq. 22).
    Paper,
}

/// Filter tuning: start covariance, process noise and the per-filter settings.
#[derive(Debug, Clone, PartialEq)]
pub struct FilterTuning {
    /// Start covariance diagonal P0 (SI, rad), in state order; missing entries count as 1.
    pub p0_diag: Vec<f64>,
    /// Process-noise diagonal per filter step Q_k (SI, rad); missing entries count as 0.
    pub q_diag: Vec<f64>,
    /// What is added to `q_diag` (`[filter.process_noise]`; the constant model adds nothing).
    pub process_noise: ProcessNoiseModel,
    /// Number of Schmidt consider parameters: the last `n_consider` states, carried in the
    /// covariance but never updated (`filter.consider`).
    pub n_consider: usize,
    /// Measurement-update iterations of the EKF-based filters (1: the standard EKF; more: the
    /// iterated EKF, [`crate::estimation::nav::EkfNav`]).
    pub update_iterations: usize,
    /// UKF constants α, β, κ.
    pub ukf: UkfParams,
    /// Density biases Δ of a multiple-model bank (seed 003 Table 4).
    pub model_bank_density_bias: Vec<f64>,
    /// DCIFAIF's fused covariance and feedback.
    pub fusion_covariance: FusionCovariance,
    /// Settings of the density-adaptation filters (`[filter.density]`; `None` when the scenario
    /// has no such section, in which case the seed-001 defaults apply where a filter needs them).
    pub density: Option<DensityFilterConfig>,
    /// Innovation gating and beacon exclusion in front of every filter (`[filter.gating]`).
    pub gating: Option<crate::estimation::gating::GatingConfig>,
}

impl FilterTuning {
    /// The density-adaptation settings, or seed 001's defaults.
    pub fn density_settings(&self) -> DensityFilterConfig {
        self.density.clone().unwrap_or_default()
    }
}

/// Everything a navigation filter may know.
#[derive(Debug, Clone)]
pub struct Onboard {
    /// Name of the scenario this was built from (for messages only).
    pub scenario_name: String,
    /// The filter's dynamics: equations of motion, planet, onboard atmosphere, vehicle constants
    /// as the filter believes them, augmented states.
    pub model: EntryModel<AtmosphereModel>,
    /// Pre-flight climatology: the mean atmosphere the onboard model was fitted to (in our
    /// scenarios the truth's mean profile *before* any per-run perturbation and density bias).
    /// Only UKF-AC uses it, for its initial correction factor 𝒦₀ (seed 001 §V.B) when
    /// `filter.density.ac_initial` is not given. It is not the atmosphere of a run.
    pub climatology: AtmosphereModel,
    /// Deterministic measurement model (IMU frame, heating constants).
    pub measurement: MeasurementModel,
    /// Measurement channels in epoch-slot order.
    pub channels: Vec<OnboardChannel>,
    /// Beacons (their ephemerides are known onboard), in scenario order.
    pub beacons: Vec<Beacon>,
    /// Beacon names, in scenario order.
    pub beacon_names: Vec<String>,
    /// `beacons`' states at the measurement epochs (the scenario's table, shared).
    pub ephemerides: Arc<EphemerisTable>,
    /// Longest prediction sub-step \[s\] (`timing.filter_step_s`).
    pub filter_step_s: f64,
    /// Commanded bank angle at the start \[rad\] (the scenario's `truth.bank_deg`, which is the
    /// guidance command, known onboard).
    pub initial_bank: f64,
    /// Nominal initial estimate: six kinematic states in the filter model's coordinates, then
    /// the augmented states.
    pub initial_estimate: Vec<f64>,
    /// USKF-NN density networks loaded onboard in place of the built-in file named by
    /// `filter.density.network` (e.g. networks just trained); `None` loads that file.
    pub density_networks: Option<DensityNetworkSet>,
    /// Tuning.
    pub tuning: FilterTuning,
    /// Filters with their own tuning in place of [`Onboard::tuning`]'s Q and the channels' assumed
    /// noise (`[filter.tuned.<name>]`); [`Onboard::for_filter`] applies them.
    pub per_filter: Vec<FilterRetune>,
}

/// One filter's own tuning: its process-noise diagonal and a factor on the assumed noise of each
/// channel (relative to [`Onboard::channels`]).
#[derive(Debug, Clone, PartialEq)]
pub struct FilterRetune {
    /// The filter.
    pub kind: FilterKind,
    /// Its process-noise diagonal per filter step (SI, rad).
    pub q_diag: Vec<f64>,
    /// Its process-noise model.
    pub process_noise: ProcessNoiseModel,
    /// Factor on channel `c`'s assumed 1σ noise (missing factors are 1).
    pub noise_factor: Vec<f64>,
}

impl Onboard {
    /// Filter state dimension (6 kinematic + augmented states).
    pub fn state_dim(&self) -> usize {
        self.model.state_dim()
    }

    /// Inertial (position, velocity) of every beacon at time `t` (the ephemerides, tabulated at
    /// the measurement epochs).
    pub fn beacon_states(&self, t: f64) -> Cow<'_, [BeaconState]> {
        self.ephemerides.states_at(&self.beacons, t)
    }

    /// The same onboard view with process-noise diagonal `q_diag` and the assumed measurement noise
    /// of channel `c` times `noise_factor[c]` (missing factors are 1): a re-tuned filter. Its
    /// tuning serves every filter (per-filter tunings are dropped).
    pub fn with_tuning(&self, q_diag: &[f64], noise_factor: &[f64]) -> Onboard {
        let mut out = self.clone();
        out.per_filter.clear();
        out.tuning.q_diag = q_diag.to_vec();
        for (c, ch) in out.channels.iter_mut().enumerate() {
            if let Some(&f) = noise_factor.get(c) {
                ch.noise = ch.noise.scaled(f);
            }
        }
        out
    }

    /// The onboard view filter `kind` is built from: this one, or with the filter's own tuning
    /// (`[filter.tuned.<name>]`) when it has one.
    pub fn for_filter(self: &Arc<Self>, kind: FilterKind) -> Arc<Onboard> {
        match self.per_filter.iter().find(|r| r.kind == kind) {
            Some(r) => {
                let mut out = self.with_tuning(&r.q_diag, &r.noise_factor);
                out.tuning.process_noise = r.process_noise;
                Arc::new(out)
            }
            None => Arc::clone(self),
        }
    }

    /// Indices of the beacons that have at least one radio channel.
    pub fn radio_beacons(&self) -> Vec<usize> {
        (0..self.beacons.len())
            .filter(|&b| self.channels.iter().any(|c| c.channel.beacon() == Some(b)))
            .collect()
    }
}
