//! [`AugmentedParam`]: the constant parameters a filter may carry beside the six kinematic
//! states (augmented or consider): density scale, C_D S/m, L/D, accelerometer biases, ….

use serde::Deserialize;
use serde::Serialize;

/// A parameter appended to the state vector: zero dynamics (a random constant; a random walk
/// with the filter's process noise), except accelerometer biases under a Gauss–Markov model.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "kebab-case")]
pub enum AugmentedParam {
    /// Reference density ρ0 [kg/m³] of the exponential model (seed 000 state 7).
    Rho0,
    /// Lift-to-drag ratio (seed 000 state 8, seed 001 state 8).
    LiftToDrag,
    /// C_D S/m [m²/kg] (seed 001 state 7, "B").
    CdSOverM,
    /// Density bias Δ: the density is the model's times (1 + Δ) (seed 003 eq. 6).
    DensityBias,
    /// Accelerometer bias on IMU axis x [m/s²] (added to the axis' reading).
    AccelBiasX,
    /// Accelerometer bias on IMU axis y [m/s²].
    AccelBiasY,
    /// Accelerometer bias on IMU axis z [m/s²].
    AccelBiasZ,
}

impl AugmentedParam {
    /// Column name used in reports (SI units in the suffix).
    pub fn name(self) -> &'static str {
        match self {
            AugmentedParam::Rho0 => "rho0_kgm3",
            AugmentedParam::LiftToDrag => "lift_to_drag",
            AugmentedParam::CdSOverM => "cd_s_over_m_m2kg",
            AugmentedParam::DensityBias => "density_bias",
            AugmentedParam::AccelBiasX => "accel_bias_x_mps2",
            AugmentedParam::AccelBiasY => "accel_bias_y_mps2",
            AugmentedParam::AccelBiasZ => "accel_bias_z_mps2",
        }
    }

    /// The name in scenario files (`filter.augment`).
    pub fn config_name(self) -> &'static str {
        match self {
            AugmentedParam::Rho0 => "rho0",
            AugmentedParam::LiftToDrag => "lift-to-drag",
            AugmentedParam::CdSOverM => "cd-s-over-m",
            AugmentedParam::DensityBias => "density-bias",
            AugmentedParam::AccelBiasX => "accel-bias-x",
            AugmentedParam::AccelBiasY => "accel-bias-y",
            AugmentedParam::AccelBiasZ => "accel-bias-z",
        }
    }

    /// The IMU axis of an accelerometer-bias state.
    pub fn accel_axis(self) -> Option<u8> {
        match self {
            AugmentedParam::AccelBiasX => Some(0),
            AugmentedParam::AccelBiasY => Some(1),
            AugmentedParam::AccelBiasZ => Some(2),
            _ => None,
        }
    }
}
