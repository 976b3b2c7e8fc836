//! Sensor suite as written in a scenario file.

use super::channels::{HeatingModel, MeasurementModel};
use super::imu::ImuFrame;
use serde::{Deserialize, Serialize};
use thiserror::Error;

/// Errors in a sensor description.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum SensorError {
    /// A value outside its physical range.
    #[error("{field} = {value} is out of range: {allowed}")]
    OutOfRange {
        /// Dotted path of the field in the scenario file.
        field: String,
        /// The offending value.
        value: String,
        /// The allowed range, in words.
        allowed: String,
    },
}

fn check(field: &str, value: f64, ok: bool, allowed: &str) -> Result<(), SensorError> {
    if ok && value.is_finite() {
        Ok(())
    } else {
        Err(SensorError::OutOfRange {
            field: field.into(),
            value: value.to_string(),
            allowed: allowed.into(),
        })
    }
}

fn check_rate(field: &str, rate: f64) -> Result<(), SensorError> {
    check(
        field,
        rate,
        rate > 0.0 && rate <= 1000.0,
        "must be > 0 and <= 1000 Hz",
    )
}

/// Accelerometer triad.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ImuConfig {
    /// Sample rate \[Hz\].
    pub rate_hz: f64,
    /// Angle of attack \[deg\]; when given the IMU reports in the body frame (seed 001 eq. 12),
    /// otherwise in the velocity frame (seed 000 eq. 5).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub angle_of_attack_deg: Option<f64>,
    /// White-noise 1σ per axis [m/s²].
    pub noise_sigma_mps2: f64,
    /// True constant bias per axis [m/s²] (seed 000: −0.03, not estimated by the filters).
    #[serde(default, with = "crate::fixed_len::array")]
    #[schemars(with = "[f64; 3]")]
    pub bias_mps2: [f64; 3],
}

/// Dynamic-pressure sensor (seed 001 eq. 14, seed 003 eq. 11).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AirDataConfig {
    /// Sample rate \[Hz\].
    pub rate_hz: f64,
    /// White-noise 1σ as a fraction of the reading (0.05 = 5 %).
    pub noise_fraction: f64,
}

fn default_k() -> f64 {
    1.9027e-4
}

/// Convective-heating sensor (seed 001 eq. 15).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct HeatingConfig {
    /// Sample rate \[Hz\].
    pub rate_hz: f64,
    /// White-noise 1σ as a fraction of the reading.
    pub noise_fraction: f64,
    /// Nose radius R_n \[m\].
    pub nose_radius_m: f64,
    /// Sutton–Graves constant k [kg^½/m] (default 1.9027e-4, Mars, seed 001).
    #[serde(default = "default_k")]
    pub sutton_graves_k: f64,
}

/// A radio measurement type taken from every beacon that has a noise level for it.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RadioConfig {
    /// Sample rate \[Hz\].
    pub rate_hz: f64,
}

/// The onboard sensor suite; absent sections are sensors the vehicle does not carry.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct SensorsConfig {
    /// Accelerometers.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub imu: Option<ImuConfig>,
    /// Dynamic pressure.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub dynamic_pressure: Option<AirDataConfig>,
    /// Convective heating.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub heating: Option<HeatingConfig>,
    /// Two-way range to beacons.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub range: Option<RadioConfig>,
    /// Range-rate to beacons.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub range_rate: Option<RadioConfig>,
}

impl SensorsConfig {
    /// Check every field's physical range; errors name the field (prefixed by `prefix`).
    pub fn validate(&self, prefix: &str) -> Result<(), SensorError> {
        if let Some(imu) = &self.imu {
            check_rate(&format!("{prefix}.imu.rate_hz"), imu.rate_hz)?;
            let f = format!("{prefix}.imu.noise_sigma_mps2");
            check(
                &f,
                imu.noise_sigma_mps2,
                imu.noise_sigma_mps2 > 0.0 && imu.noise_sigma_mps2 < 10.0,
                "must be > 0 and < 10 m/s²",
            )?;
            for (k, b) in imu.bias_mps2.iter().enumerate() {
                check(
                    &format!("{prefix}.imu.bias_mps2[{k}]"),
                    *b,
                    b.abs() < 10.0,
                    "must be within ±10 m/s²",
                )?;
            }
            if let Some(a) = imu.angle_of_attack_deg {
                check(
                    &format!("{prefix}.imu.angle_of_attack_deg"),
                    a,
                    a.abs() <= 90.0,
                    "must be within ±90°",
                )?;
            }
        }
        if let Some(q) = &self.dynamic_pressure {
            check_rate(&format!("{prefix}.dynamic_pressure.rate_hz"), q.rate_hz)?;
            let f = format!("{prefix}.dynamic_pressure.noise_fraction");
            check(
                &f,
                q.noise_fraction,
                q.noise_fraction > 0.0 && q.noise_fraction < 1.0,
                "must be > 0 and < 1 (fraction of reading)",
            )?;
        }
        if let Some(h) = &self.heating {
            check_rate(&format!("{prefix}.heating.rate_hz"), h.rate_hz)?;
            let f = format!("{prefix}.heating.noise_fraction");
            check(
                &f,
                h.noise_fraction,
                h.noise_fraction > 0.0 && h.noise_fraction < 1.0,
                "must be > 0 and < 1 (fraction of reading)",
            )?;
            let f = format!("{prefix}.heating.nose_radius_m");
            check(
                &f,
                h.nose_radius_m,
                h.nose_radius_m > 0.0 && h.nose_radius_m < 20.0,
                "must be > 0 and < 20 m",
            )?;
            let f = format!("{prefix}.heating.sutton_graves_k");
            check(
                &f,
                h.sutton_graves_k,
                h.sutton_graves_k > 0.0 && h.sutton_graves_k < 1.0,
                "must be > 0 and < 1 kg^0.5/m",
            )?;
        }
        if let Some(r) = &self.range {
            check_rate(&format!("{prefix}.range.rate_hz"), r.rate_hz)?;
        }
        if let Some(r) = &self.range_rate {
            check_rate(&format!("{prefix}.range_rate.rate_hz"), r.rate_hz)?;
        }
        Ok(())
    }

    /// The deterministic measurement model these sensors imply.
    pub fn measurement_model(&self) -> MeasurementModel {
        let imu_frame = match self.imu.as_ref().and_then(|i| i.angle_of_attack_deg) {
            Some(a) => ImuFrame::Body {
                angle_of_attack: a.to_radians(),
            },
            None => ImuFrame::Velocity,
        };
        let heating = match &self.heating {
            Some(h) => HeatingModel {
                k: h.sutton_graves_k,
                nose_radius: h.nose_radius_m,
            },
            None => HeatingModel {
                k: default_k(),
                nose_radius: 1.0,
            },
        };
        MeasurementModel { imu_frame, heating }
    }
}
