//! [`NoiseInflation`]: the factors on the measurement noise a filter assumes, per channel kind
//! (`[filter.noise_inflation]`), and their largest accepted value.

use serde::{Deserialize, Serialize};

/// The default of every factor (serde).
fn one() -> f64 {
    1.0
}

/// The largest factor of [`NoiseInflation`] a scenario accepts.
pub const MAX_NOISE_INFLATION: f64 = 1e3;

/// Factors on the 1σ measurement noise the filter assumes, per channel kind
/// (`[filter.noise_inflation]`; every key defaults to 1, each in (0, [`MAX_NOISE_INFLATION`]]).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NoiseInflation {
    /// Accelerometers (on top of `filter.imu_sigma_mps2`).
    #[serde(default = "one")]
    pub accel: f64,
    /// Dynamic pressure.
    #[serde(default = "one")]
    pub dynamic_pressure: f64,
    /// Heating.
    #[serde(default = "one")]
    pub heating: f64,
    /// Range.
    #[serde(default = "one")]
    pub range: f64,
    /// Range-rate.
    #[serde(default = "one")]
    pub range_rate: f64,
}

impl Default for NoiseInflation {
    fn default() -> Self {
        NoiseInflation {
            accel: 1.0,
            dynamic_pressure: 1.0,
            heating: 1.0,
            range: 1.0,
            range_rate: 1.0,
        }
    }
}

impl NoiseInflation {
    /// The factor of channel kind `channel`.
    pub fn factor(&self, channel: crate::sensors::Channel) -> f64 {
        use crate::sensors::Channel;
        match channel {
            Channel::Accel(_) => self.accel,
            Channel::DynamicPressure => self.dynamic_pressure,
            Channel::Heating => self.heating,
            Channel::Range(_) => self.range,
            Channel::RangeRate(_) => self.range_rate,
        }
    }

    /// Set the factor of channel kind `channel`.
    pub fn set_factor(&mut self, channel: crate::sensors::Channel, value: f64) {
        use crate::sensors::Channel;
        match channel {
            Channel::Accel(_) => self.accel = value,
            Channel::DynamicPressure => self.dynamic_pressure = value,
            Channel::Heating => self.heating = value,
            Channel::Range(_) => self.range = value,
            Channel::RangeRate(_) => self.range_rate = value,
        }
    }
}
