//! The scenario file format (TOML), as serde structures.
//!
//! Units at this boundary are the ones engineers write: km and degrees for geometry, m/s for
//! speeds, SI for everything else; each field name carries its unit. Field-by-field range checks
//! live in [`super::validate`]. Every struct rejects unknown fields.

pub use super::noise_inflation::{MAX_NOISE_INFLATION, NoiseInflation};
use crate::atmosphere::{AtmosphereConfig, PerturbationConfig};
use crate::beacons::BeaconConfig;
use crate::dynamics::{AugmentedParam, DynamicsKind};
pub use crate::estimation::FusionCovariance;
pub use crate::estimation::adaptive::{DensityFilterConfig, DensityTrainingConfig};
pub use crate::estimation::gating::GatingConfig;
pub use crate::estimation::{AeroScaledNoise, MAX_AERO_FRACTION, ProcessNoiseModel};
use crate::frames::HeadingConvention;
pub use crate::guidance::GuidanceConfig;
use crate::sensors::{FaultConfig, SensorsConfig};
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// A complete scenario: truth world, onboard filter model, sensors, beacons, dispersions, timing.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ScenarioConfig {
    /// Short identifier, e.g. `four-beacon-fusion`.
    pub name: String,
    /// One-paragraph description.
    pub description: String,
    /// Where the numbers come from (paper, tables, equations).
    pub reference: String,
    /// Convention of every heading number in this file.
    pub heading_convention: HeadingConvention,
    /// Planet constants (overrides of the Mars defaults).
    #[serde(default)]
    pub planet: PlanetConfig,
    /// Durations and steps.
    pub timing: TimingConfig,
    /// The simulated world.
    pub truth: TruthConfig,
    /// The onboard navigation model.
    pub filter: FilterConfig,
    /// Onboard sensors.
    #[serde(default)]
    pub sensors: SensorsConfig,
    /// Radio beacons.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub beacons: Vec<BeaconConfig>,
    /// Take radio measurements even when a beacon is below the horizon (needed to reproduce
    /// the DCIFAIF fusion paper \[P0\], whose beacons are all on the far side of Mars; see
    /// docs/references.md).
    #[serde(default)]
    pub ignore_visibility: bool,
    /// Run although an initial state lies outside what a Mars entry plausibly has (entry
    /// interface 80–250 km, speed 3–8 km/s, flight-path angle −30° to −5°; see
    /// `scenario::plausibility`). Without it such a value is refused, most are a unit slip
    /// (a speed in km/s, an angle in radians).
    #[serde(default, skip_serializing_if = "std::ops::Not::not")]
    pub allow_implausible: bool,
    /// Monte Carlo dispersions of the truth (1σ).
    #[serde(default)]
    pub dispersions: DispersionConfig,
    /// Monte Carlo defaults.
    #[serde(default)]
    pub monte_carlo: MonteCarloConfig,
    /// Sensor faults of the truth: range biases and outliers, accelerometer bias jumps and
    /// spikes (`[[faults]]`; beacon outages are the beacons' `outages`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub faults: Vec<FaultConfig>,
    /// Entry guidance (issue 28): the algorithm, target, rate, bank limits and deployment
    /// trigger. Absent: the constant `truth.bank_deg`. A trade's navigation Monte Carlo still
    /// flies `truth.bank_deg`; its delivery table (`sim::guided::delivery`), `guidance deliver`
    /// and `sim::guided_flight` fly the guidance.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub guidance: Option<GuidanceConfig>,
}

/// Optional planet-constant overrides.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PlanetConfig {
    /// μ [m³/s²].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mu_m3s2: Option<f64>,
    /// Reference radius \[km\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius_km: Option<f64>,
    /// Rotation rate [rad/s].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rotation_rate_rad_s: Option<f64>,
}

/// Durations and integration steps.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TimingConfig {
    /// Length of the entry simulated \[s\].
    pub duration_s: f64,
    /// Fixed RK4 step of the truth integration \[s\]; every sensor period must be a multiple of it.
    pub truth_step_s: f64,
    /// Filter cycle \[s\].
    pub filter_step_s: f64,
    /// Optional parachute-deployment trigger: stop when the planet-relative speed falls below this.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub stop_speed_mps: Option<f64>,
}

/// An initial state, either spherical (planet-relative velocity) or Cartesian inertial.
///
/// Exactly one form must be complete. Also used for 1σ dispersions, with the same units.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct StateConfig {
    /// Radius \[km\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub radius_km: Option<f64>,
    /// Longitude \[deg\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lon_deg: Option<f64>,
    /// Latitude \[deg\].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lat_deg: Option<f64>,
    /// Planet-relative speed [m/s].
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub speed_mps: Option<f64>,
    /// Flight-path angle \[deg\], positive up.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fpa_deg: Option<f64>,
    /// Heading \[deg\] in the file's `heading_convention`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub heading_deg: Option<f64>,
    /// Inertial position \[km\].
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        with = "crate::fixed_len::option_array"
    )]
    #[schemars(with = "Option<[f64; 3]>")]
    pub position_km: Option<[f64; 3]>,
    /// Inertial velocity [m/s].
    #[serde(
        default,
        skip_serializing_if = "Option::is_none",
        with = "crate::fixed_len::option_array"
    )]
    #[schemars(with = "Option<[f64; 3]>")]
    pub velocity_mps: Option<[f64; 3]>,
}

/// Vehicle aerodynamics: give either `cd_s_over_m_m2kg` or `ballistic_coefficient_kgm2`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct VehicleConfig {
    /// C_D·S/m [m²/kg] (seed 000 "CdS/m", seed 001 "B").
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub cd_s_over_m_m2kg: Option<f64>,
    /// Ballistic coefficient m/(C_D S) [kg/m²] (seed 003).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ballistic_coefficient_kgm2: Option<f64>,
    /// Lift-to-drag ratio.
    pub lift_to_drag: f64,
}

/// The simulated world.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TruthConfig {
    /// Equations of motion.
    pub dynamics: DynamicsKind,
    /// Nominal initial state.
    pub initial: StateConfig,
    /// Vehicle.
    pub vehicle: VehicleConfig,
    /// Mean atmosphere.
    pub atmosphere: AtmosphereConfig,
    /// Random, altitude-correlated perturbation of the atmosphere, drawn per run.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub perturbation: Option<PerturbationConfig>,
    /// Constant density bias Δ: ρ = ρ_model·(1 + Δ) (seed 003 eq. 6).
    #[serde(default)]
    pub density_bias: f64,
    /// Bank angle \[deg\] (0 in every paper scenario).
    #[serde(default)]
    pub bank_deg: f64,
}

/// UKF sigma-point constants (seed 001 eq. 41–50).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct UkfConfig {
    /// Spread α.
    pub alpha: f64,
    /// Prior-knowledge β (2 for Gaussian).
    pub beta: f64,
    /// κ; absent means 3 − L (seed 001 §IV.B).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub kappa: Option<f64>,
}

impl Default for UkfConfig {
    fn default() -> Self {
        UkfConfig {
            alpha: 1.0,
            beta: 2.0,
            kappa: None,
        }
    }
}

/// The onboard navigation model. Covariances are in SI units and radians, in state order
/// `[r|x, lon|y, lat|z, v|vx, fpa|vy, heading|vz, augmented…]`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FilterConfig {
    /// Equations of motion of the filter.
    pub dynamics: DynamicsKind,
    /// Filter's vehicle constants (may differ from the truth: seed 000's C_D S/m error).
    pub vehicle: VehicleConfig,
    /// Onboard density model.
    pub atmosphere: AtmosphereConfig,
    /// Augmented states the filter estimates, after the six kinematic states.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub augment: Vec<AugmentedParam>,
    /// Schmidt consider parameters, after the augmented states: carried in the state and the
    /// covariance (their uncertainty enters every gain) but never updated by a measurement.
    /// Supported by `ekf`, `ukf`, `ci`, `dcifaif` and the banks.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub consider: Vec<AugmentedParam>,
    /// Start values of the consider parameters, in `consider` order (SI).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub initial_consider: Vec<f64>,
    /// Time constant τ \[s\] of the accelerometer-bias states (`accel-bias-x/y/z`) as first-order
    /// Gauss–Markov processes ḃ = −b/τ; absent: random constants (ḃ = 0).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub accel_bias_tau_s: Option<f64>,
    /// Filter start; absent means the truth's nominal initial state.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub initial: Option<StateConfig>,
    /// Start values of the augmented states, in `augment` order (SI).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub initial_augmented: Vec<f64>,
    /// Start covariance diagonal P0 (SI, rad).
    pub p0_diag: Vec<f64>,
    /// Process-noise covariance diagonal per filter step Q_k (SI, rad).
    pub q_diag: Vec<f64>,
    /// What is added to `q_diag`: `model = "constant"` (the default, nothing) or
    /// `model = "aero-scaled"`, state-noise compensation scaled by the aerodynamic load
    /// (docs/process-noise.md).
    #[serde(default, skip_serializing_if = "ProcessNoiseModel::is_constant")]
    pub process_noise: ProcessNoiseModel,
    /// Accelerometer noise 1σ the filter assumes [m/s²] (default: the sensor's own). Set it larger
    /// than the sensor noise to account for errors the filter does not model, e.g. seed 000's
    /// unestimated −0.03 m/s² bias, which is 30σ of the printed R = 1e-6.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub imu_sigma_mps2: Option<f64>,
    /// Draw the filter start from N(truth, P0) in Monte Carlo runs (seed 001 §V.B) instead of
    /// using `initial` as a fixed offset (seed 000 Table 1).
    #[serde(default)]
    pub sample_initial_from_p0: bool,
    /// Measurement-update iterations of the EKF-based filters (1: the standard EKF; more:
    /// the iterated EKF, Gauss–Newton on the measurement model, for large prior errors).
    #[serde(default = "one_iteration", skip_serializing_if = "is_one_iteration")]
    pub update_iterations: usize,
    /// UKF constants.
    #[serde(default)]
    pub ukf: UkfConfig,
    /// Density biases Δ of a multiple-model bank (seed 003 Table 4).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub model_bank_density_bias: Vec<f64>,
    /// Factors on the measurement noise the filter assumes, per channel kind (1: the sensor's
    /// own; `entrynav tune` writes them when it tunes the measurement noise).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub noise_inflation: Option<NoiseInflation>,
    /// DCIFAIF: `"exact"` (default) feeds back the exact covariance of the fused estimate;
    /// `"paper"` is seed 000 eq. 20 and 22 as printed (CI bound, fed back as P_CI/ω_i).
    #[serde(default, skip_serializing_if = "is_default_fusion")]
    pub fusion_covariance: FusionCovariance,
    /// Settings of the density-adaptation filters `ukf-cm`, `ukf-ac`, `uskf-nn` (seed 001).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub density: Option<DensityFilterConfig>,
    /// One filter's own tuning in place of the shared `q_diag` and `noise_inflation`
    /// (`[filter.tuned.<filter name>]`, e.g. `[filter.tuned.ukf]`; `entrynav tune` writes them).
    #[serde(default, skip_serializing_if = "BTreeMap::is_empty")]
    pub tuned: BTreeMap<String, FilterRetuneConfig>,
    /// Innovation gating and beacon fault exclusion in front of every filter (absent: every
    /// available measurement is used).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub gating: Option<GatingConfig>,
}

/// A filter's own tuning (`[filter.tuned.<filter name>]`): each field present replaces the shared
/// one of `[filter]` for that filter only; an absent field keeps the shared value.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FilterRetuneConfig {
    /// Process-noise diagonal per filter step Q_k of this filter (SI, rad), in state order.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub q_diag: Option<Vec<f64>>,
    /// Process-noise model of this filter (in place of `filter.process_noise`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub process_noise: Option<ProcessNoiseModel>,
    /// Factors on the assumed measurement noise of this filter, per channel kind (in place of
    /// `filter.noise_inflation`, not on top of it).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub noise_inflation: Option<NoiseInflation>,
}

/// Monte Carlo dispersions (1σ) of the truth.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct DispersionConfig {
    /// 1σ of the initial state, same form and units as `truth.initial`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub initial: Option<StateConfig>,
    /// 1σ of C_D S/m [m²/kg].
    #[serde(default)]
    pub cd_s_over_m_m2kg: f64,
    /// 1σ of L/D.
    #[serde(default)]
    pub lift_to_drag: f64,
    /// 1σ of the density bias Δ.
    #[serde(default)]
    pub density_bias: f64,
    /// Clip |Δ| to this value (seed 003: 0.10); 0 means no clipping.
    #[serde(default)]
    pub density_bias_clip: f64,
}

fn default_runs() -> usize {
    100
}

/// Monte Carlo defaults.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct MonteCarloConfig {
    /// Number of runs when none is given on the command line.
    #[serde(default = "default_runs")]
    pub runs: usize,
}

impl Default for MonteCarloConfig {
    fn default() -> Self {
        MonteCarloConfig {
            runs: default_runs(),
        }
    }
}

impl FilterConfig {
    /// The filter's augmented states in state order: `augment`, then `consider`.
    pub fn state_params(&self) -> Vec<AugmentedParam> {
        self.augment.iter().chain(&self.consider).copied().collect()
    }

    /// Filter state dimension: 6 kinematic + augmented + consider states.
    pub fn state_dim(&self) -> usize {
        6 + self.augment.len() + self.consider.len()
    }
}

fn is_default_fusion(f: &FusionCovariance) -> bool {
    *f == FusionCovariance::default()
}

fn one_iteration() -> usize {
    1
}

fn is_one_iteration(n: &usize) -> bool {
    *n == 1
}
