//! The settings of seed 001's density-adaptation filters and of the offline network training
//! (`[filter.density]` and `[filter.density.training]` of a scenario file).
//!
//! They live here, beside the filters that use them, so that the estimation layer needs nothing
//! from the scenario layer; the scenario format re-exports them.

use crate::atmosphere::AtmosphereConfig;
use serde::{Deserialize, Serialize};

fn d_cm_batch() -> usize {
    10
}
fn d_ac_p0() -> f64 {
    1e-10
}
fn d_ac_q() -> f64 {
    1e-7
}
fn d_network() -> String {
    "msl-airdata-density-nn.toml".to_string()
}
fn d_tau() -> f64 {
    5.0
}
fn d_pss() -> f64 {
    1e-3
}
fn d_pc0() -> f64 {
    1e-10
}
fn d_beta1() -> f64 {
    0.1
}
fn d_beta2() -> f64 {
    0.9
}
fn d_eps() -> f64 {
    1e-8
}
fn d_step() -> f64 {
    0.01
}
fn d_patience() -> usize {
    1
}
fn d_threshold() -> f64 {
    5.0
}
fn d_max_iter() -> usize {
    100
}
fn d_window() -> usize {
    1
}
fn d_slope_sigma() -> f64 {
    0.1
}
fn d_slope_u_sigma() -> f64 {
    3.3333e-3
}

/// Settings of the density-adaptation filters of seed 001 (`[filter.density]`); every key is
/// optional and defaults to the paper's value (§V.B, Table 4) or, where the paper gives none,
/// to ours (documented per field).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DensityFilterConfig {
    /// UKF-CM: Myers–Tapley batch size in filter steps (seed 001: 10).
    #[serde(default = "d_cm_batch")]
    pub cm_batch: usize,
    /// UKF-AC: initial variance of the correction factor 𝒦 (seed 001: 1e-10).
    #[serde(default = "d_ac_p0")]
    pub ac_p0: f64,
    /// UKF-AC: random-walk variance of 𝒦 per filter step (seed 001: 1e-7).
    #[serde(default = "d_ac_q")]
    pub ac_q: f64,
    /// UKF-AC: initial 𝒦; absent means the ratio of the pre-flight climatology (`climatology`,
    /// `Onboard::climatology`) to the onboard model at the filter's initial altitude (our
    /// reading of "the ratio between the true density and the nominal density").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ac_initial: Option<f64>,
    /// The pre-flight climatology the vehicle carries: the mean atmosphere the onboard model was
    /// fitted to (an atmosphere description, e.g. `{ model = "mars-mean" }` or an averaged
    /// Mars-GRAM table file). Absent: the filter's own atmosphere (`filter.atmosphere`), so
    /// UKF-AC starts at 𝒦₀ = 1. It is a filter-side setting: a scenario's truth atmosphere
    /// never reaches a filter, whatever it is.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub climatology: Option<AtmosphereConfig>,
    /// USKF-NN: network file, the name of a built-in (`msl-airdata-density-nn.toml`, one network;
    /// `msl-airdata-density-nn-bands.toml`, one per altitude band).
    #[serde(default = "d_network")]
    pub network: String,
    /// USKF-NN: time constant τ of the consider parameter's ECRV \[s\] (seed 001: 5).
    #[serde(default = "d_tau")]
    pub consider_tau_s: f64,
    /// USKF-NN: steady-state variance P_ss of the consider parameter (seed 001: 1e-3).
    #[serde(default = "d_pss")]
    pub consider_pss: f64,
    /// USKF-NN: initial variance P_c,0 of the consider parameter (seed 001: 1e-10).
    #[serde(default = "d_pc0")]
    pub consider_p0: f64,
    /// USKF-NN adaptation: Adam β₁ (seed 001 Table 4: 0.1).
    #[serde(default = "d_beta1")]
    pub adam_beta1: f64,
    /// USKF-NN adaptation: Adam β₂ (seed 001 Table 4: 0.9).
    #[serde(default = "d_beta2")]
    pub adam_beta2: f64,
    /// USKF-NN adaptation: Adam ε (not given in seed 001; Adam's usual 1e-8).
    #[serde(default = "d_eps")]
    pub adam_epsilon: f64,
    /// USKF-NN adaptation: step size numerator, α_L = adam_step / k at filter step k (Table 4: 0.01).
    #[serde(default = "d_step")]
    pub adam_step: f64,
    /// USKF-NN adaptation: maximum patience p_max (Table 4: 1).
    #[serde(default = "d_patience")]
    pub patience: usize,
    /// USKF-NN adaptation: loss threshold 𝒯 above which the optimisation runs (blank in seed
    /// 001 Table 4; ours).
    #[serde(default = "d_threshold")]
    pub loss_threshold: f64,
    /// USKF-NN adaptation: cap on optimiser iterations per measurement (ours; a safety bound).
    #[serde(default = "d_max_iter")]
    pub max_iterations: usize,
    /// USKF-NN adaptation: measurement epochs in the loss, current included (1 = seed 001
    /// eq. 52; more is the window extension of seed 001 §VI).
    #[serde(default = "d_window")]
    pub window: usize,
    /// USKF-NN: epochs in the local level-and-slope correction of the network density (ours,
    /// `adaptive::local_fit`); absent = no correction (seed 001).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub slope_window: Option<usize>,
    /// USKF-NN: a priori σ of the correction's log-slope \[1/km\] (ours).
    #[serde(default = "d_slope_sigma")]
    pub slope_sigma_per_km: f64,
    /// USKF-NN: σ of one epoch's log-density in the correction's fit (ours).
    #[serde(default = "d_slope_u_sigma")]
    pub slope_log_density_sigma: f64,
    /// USKF-NN with `slope_window`: the consider parameter's variance at each update becomes
    /// the larger of `consider_pss` and the correction's one-step prediction-error variance,
    /// averaged over about this many epochs (covariance matching, ours; `nav::uskf_nn`);
    /// absent = c keeps its ECRV variance (seed 001 eq. 51).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub consider_match_epochs: Option<usize>,
    /// Offline training (seed 001 Algorithm 1) for `entrynav train-density`.
    #[serde(default)]
    pub training: DensityTrainingConfig,
}

impl Default for DensityFilterConfig {
    fn default() -> Self {
        DensityFilterConfig {
            cm_batch: d_cm_batch(),
            ac_p0: d_ac_p0(),
            ac_q: d_ac_q(),
            ac_initial: None,
            climatology: None,
            network: d_network(),
            consider_tau_s: d_tau(),
            consider_pss: d_pss(),
            consider_p0: d_pc0(),
            adam_beta1: d_beta1(),
            adam_beta2: d_beta2(),
            adam_epsilon: d_eps(),
            adam_step: d_step(),
            patience: d_patience(),
            loss_threshold: d_threshold(),
            max_iterations: d_max_iter(),
            window: d_window(),
            slope_window: None,
            slope_sigma_per_km: d_slope_sigma(),
            slope_log_density_sigma: d_slope_u_sigma(),
            consider_match_epochs: None,
            training: DensityTrainingConfig::default(),
        }
    }
}

fn d_seed() -> u64 {
    1
}
fn d_trajectories() -> usize {
    1000
}
fn d_train_duration() -> f64 {
    250.0
}
fn d_sample_interval() -> f64 {
    0.5
}
fn d_hidden() -> usize {
    100
}
fn d_epochs() -> usize {
    1000
}
fn d_batch() -> usize {
    4096
}
fn d_lr_max() -> f64 {
    1e-2
}
fn d_lr_min() -> f64 {
    1e-6
}
fn d_val() -> f64 {
    0.2
}
fn d_fit_km() -> [f64; 2] {
    [0.0, 130.0]
}

/// Offline training of the density network (seed 001 Algorithm 1, §IV.A.1), `[filter.density.training]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DensityTrainingConfig {
    /// Seed of the trajectories, the split and the initial weights.
    #[serde(default = "d_seed")]
    pub seed: u64,
    /// Simulated trajectories N (seed 001: 1000).
    #[serde(default = "d_trajectories")]
    pub trajectories: usize,
    /// Length of each trajectory \[s\] (seed 001: 250).
    #[serde(default = "d_train_duration")]
    pub duration_s: f64,
    /// Sampling interval of (r, ρ) \[s\] (seed 001: 0.5).
    #[serde(default = "d_sample_interval")]
    pub sample_interval_s: f64,
    /// Hidden neurons H (seed 001: 100).
    #[serde(default = "d_hidden")]
    pub hidden: usize,
    /// Epochs (seed 001: 1000).
    #[serde(default = "d_epochs")]
    pub epochs: usize,
    /// Mini-batch size (not given in seed 001; ours).
    #[serde(default = "d_batch")]
    pub batch_size: usize,
    /// Largest learning rate (seed 001: 1e-2).
    #[serde(default = "d_lr_max")]
    pub lr_max: f64,
    /// Smallest learning rate (seed 001: 1e-6).
    #[serde(default = "d_lr_min")]
    pub lr_min: f64,
    /// Fraction of the samples held out for validation.
    #[serde(default = "d_val")]
    pub validation_fraction: f64,
    /// Altitude range \[km\] of the truth mean profile the least-squares exponential is fitted to.
    #[serde(default = "d_fit_km", with = "crate::fixed_len::array")]
    #[schemars(with = "[f64; 2]")]
    pub fit_altitude_km: [f64; 2],
    /// Band edges \[km\] for one network per altitude band (the multi-network extension of seed
    /// 001 §VI), e.g. `[0, 40, 70, 130]`; empty = one network trained on one exponential.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub bands_km: Vec<f64>,
}

impl Default for DensityTrainingConfig {
    fn default() -> Self {
        DensityTrainingConfig {
            seed: d_seed(),
            trajectories: d_trajectories(),
            duration_s: d_train_duration(),
            sample_interval_s: d_sample_interval(),
            hidden: d_hidden(),
            epochs: d_epochs(),
            batch_size: d_batch(),
            lr_max: d_lr_max(),
            lr_min: d_lr_min(),
            validation_fraction: d_val(),
            fit_altitude_km: d_fit_km(),
            bands_km: Vec::new(),
        }
    }
}
