//! `[guidance]`: which algorithm, its target, rate, limits and parameters, and the one function
//! that builds a guidance from it and the onboard model.

use super::algorithm::Guidance;
use super::apollo::{ApolloConfig, ApolloGuidance};
use super::deploy::DeployBox;
use super::error::GuidanceError;
use super::fnpeg::{Fnpeg, FnpegConfig};
use super::lateral::{Lateral, LateralConfig};
use super::limits::BankLimits;
use super::longitudinal::{LongModel, Trigger};
use super::reference::{ReferenceSettings, ReferenceTrajectory};
use super::safeguard::AltitudeSafeguard;
use super::target::{Target, destination};
use crate::atmosphere::Atmosphere;
use crate::dynamics::EntryModel;
use serde::{Deserialize, Serialize};

/// The guidance algorithm.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum GuidanceAlgorithm {
    /// Apollo final-phase guidance as adapted for MSL (Mendeck & Craig 2011).
    Apollo,
    /// Fully numerical predictor–corrector (Lu 2014).
    Fnpeg,
}

/// The atmosphere guidance predicts with.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum GuidanceAtmosphere {
    /// The pre-flight climatology (`filter.density.climatology`, default the filter's own
    /// atmosphere): what a reference trajectory is designed on before flight.
    #[default]
    Climatology,
    /// The filter's onboard atmosphere model (`filter.atmosphere`).
    Filter,
}

/// The deployment target: a point, or a downrange along the entry heading.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TargetConfig {
    /// Target latitude \[deg\] (with `lon_deg`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lat_deg: Option<f64>,
    /// Target longitude \[deg\] (with `lat_deg`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub lon_deg: Option<f64>,
    /// Target downrange \[km\] from the entry point along the entry heading's great circle
    /// (instead of `lat_deg`/`lon_deg`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub range_km: Option<f64>,
}

/// `[guidance]`: entry guidance in place of the constant `truth.bank_deg`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GuidanceConfig {
    /// `apollo` or `fnpeg`.
    pub algorithm: GuidanceAlgorithm,
    /// Guidance cycle rate \[Hz\].
    #[serde(default = "default_rate")]
    pub rate_hz: f64,
    /// Constant bank of the reference trajectory \[deg\] (Apollo's reference; FNPEG's start σ0).
    pub reference_bank_deg: f64,
    /// Target; absent: the landing point of the reference trajectory (its trigger point on the
    /// entry heading's great circle).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub target: Option<TargetConfig>,
    /// Deployment trigger, `{ speed_mps = … }`, `{ dynamic_pressure_pa = … }` or the Mars 2020
    /// range trigger `{ range = { nominal_speed_mps = …, backstop_speed_mps = … } }`
    /// (`guidance::deploy`).
    pub trigger: Trigger,
    /// The box every deployment must meet (speed, dynamic pressure, altitude on the truth at
    /// deployment; the range trigger's speed and pressure window).
    #[serde(default)]
    pub deploy_box: DeployBox,
    /// Smallest commanded bank magnitude \[deg\].
    #[serde(default)]
    pub bank_min_deg: f64,
    /// Largest commanded bank magnitude \[deg\].
    #[serde(default = "default_bank_max")]
    pub bank_max_deg: f64,
    /// Bank rate limit \[deg/s\].
    #[serde(default = "default_rate_limit")]
    pub bank_rate_limit_deg_s: f64,
    /// Bank acceleration limit \[deg/s²\].
    #[serde(default = "default_accel_limit")]
    pub bank_accel_limit_deg_s2: f64,
    /// The atmosphere of guidance's onboard model (`climatology` or `filter`); the vehicle
    /// constants and planet are always the filter's.
    #[serde(default)]
    pub atmosphere: GuidanceAtmosphere,
    /// Crossrange corridor of the bank reversals.
    #[serde(default)]
    pub lateral: LateralConfig,
    /// Apollo settings.
    #[serde(default)]
    pub apollo: ApolloConfig,
    /// FNPEG settings.
    #[serde(default)]
    pub fnpeg: FnpegConfig,
    /// Altitude safeguard floor \[m\], 0 to 50000: below the reference's peak-drag speed,
    /// when the onboard prediction from the estimate says that the algorithm's bank, flown until
    /// the vehicle could roll to lift-up, would reach the deployment trigger below this altitude
    /// even with lift-up after that, the bank magnitude is capped at the largest one that still
    /// can (altitude has priority over range; `guidance::safeguard`). Absent: no safeguard.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub min_deploy_altitude_m: Option<f64>,
}

fn default_rate() -> f64 {
    1.0
}
fn default_bank_max() -> f64 {
    180.0
}
fn default_rate_limit() -> f64 {
    20.0
}
fn default_accel_limit() -> f64 {
    5.0
}

/// Integration step of the reference trajectory \[s\].
pub const REFERENCE_STEP_S: f64 = 0.25;
/// Longest reference or prediction \[s\].
pub const MAX_FLIGHT_S: f64 = 1500.0;

impl GuidanceConfig {
    /// The bank limits in radians, checked.
    pub fn limits(&self) -> Result<BankLimits, GuidanceError> {
        BankLimits {
            min_magnitude: self.bank_min_deg.to_radians(),
            max_magnitude: self.bank_max_deg.to_radians(),
            rate_max: self.bank_rate_limit_deg_s.to_radians(),
            accel_max: self.bank_accel_limit_deg_s2.to_radians(),
        }
        .checked()
    }

    /// The guidance period \[s\].
    pub fn period_s(&self) -> f64 {
        1.0 / self.rate_hz
    }
}

/// A guidance built from `[guidance]`, with what it was built on.
pub struct BuiltGuidance {
    /// The algorithm.
    pub guidance: Box<dyn Guidance + Send>,
    /// The reference trajectory (Apollo's profiles; FNPEG's final energy).
    pub reference: ReferenceTrajectory,
    /// The target.
    pub target: Target,
    /// Bank limits.
    pub limits: BankLimits,
}

/// The reference trajectory of `config` from the onboard `model` and the onboard entry state
/// `entry` (`[r, lon, lat, v, fpa, heading]`), and the target (given, or its landing point).
pub fn reference_and_target<A: Atmosphere>(
    config: &GuidanceConfig,
    model: &EntryModel<A>,
    entry: &[f64; 6],
) -> Result<(ReferenceTrajectory, Target), GuidanceError> {
    let lm = LongModel {
        model,
        density_scale: 1.0,
        trigger: config.trigger,
    };
    let reference = ReferenceTrajectory::build(
        &lm,
        entry[0],
        entry[3],
        entry[4],
        &ReferenceSettings {
            bank: config.reference_bank_deg.to_radians(),
            step_s: REFERENCE_STEP_S,
            max_time_s: MAX_FLIGHT_S,
        },
    )?;
    let [_, lon, lat, _, _, psi] = *entry;
    let target = match config.target {
        Some(TargetConfig {
            lat_deg: Some(la),
            lon_deg: Some(lo),
            ..
        }) => Target {
            lat: la.to_radians(),
            lon: lo.to_radians(),
        },
        Some(TargetConfig {
            range_km: Some(km), ..
        }) => destination(lat, lon, psi, km * 1e3 / model.planet.radius),
        _ => destination(lat, lon, psi, reference.theta_final),
    };
    Ok((reference, target))
}

/// Build the guidance of `config` on the onboard `model` from the onboard entry state `entry`.
pub fn build_guidance<A: Atmosphere + Clone + Send + 'static>(
    config: &GuidanceConfig,
    model: &EntryModel<A>,
    entry: &[f64; 6],
) -> Result<BuiltGuidance, GuidanceError> {
    let limits = config.limits()?;
    if !(config.rate_hz > 0.0 && config.rate_hz.is_finite()) {
        return Err(GuidanceError::Parameter {
            name: "rate_hz",
            value: config.rate_hz,
            allowed: "must be > 0",
        });
    }
    let (reference, target) = reference_and_target(config, model, entry)?;
    let lateral = Lateral::new(config.lateral, 0.0);
    let guidance: Box<dyn Guidance + Send> = match config.algorithm {
        GuidanceAlgorithm::Apollo => Box::new(ApolloGuidance::new(
            config.apollo,
            reference.clone(),
            target,
            model.vehicle.lift_to_drag,
            model.planet.radius,
            limits,
            lateral,
        )),
        GuidanceAlgorithm::Fnpeg => {
            let xf = reference.final_state;
            let final_energy = model.planet.mu / xf[1] - 0.5 * xf[2] * xf[2];
            let sigma0 = limits.clamp_magnitude(reference.bank.abs());
            Box::new(Fnpeg {
                config: config.fnpeg,
                model: model.clone(),
                trigger: config.trigger,
                target,
                final_energy,
                limits,
                lateral,
                sigma0,
                density_scale: 1.0,
                predictions: 0,
                anchor_energy: model.planet.mu / entry[0] - 0.5 * entry[3] * entry[3],
                max_time_s: MAX_FLIGHT_S,
            })
        }
    };
    let guidance: Box<dyn Guidance + Send> = match config.min_deploy_altitude_m {
        Some(floor_m) => {
            if !(floor_m >= 0.0 && floor_m.is_finite()) {
                return Err(GuidanceError::Parameter {
                    name: "min_deploy_altitude_m",
                    value: floor_m,
                    allowed: "must be >= 0 m and finite",
                });
            }
            Box::new(AltitudeSafeguard {
                inner: guidance,
                model: model.clone(),
                trigger: config.trigger,
                floor_m,
                limits,
                density_scale: 1.0,
                max_time_s: MAX_FLIGHT_S,
                active_below_mps: reference.peak_drag_speed(),
                period_s: config.period_s(),
                activations: 0,
                predictions: 0,
            })
        }
        None => guidance,
    };
    Ok(BuiltGuidance {
        guidance,
        reference,
        target,
        limits,
    })
}
