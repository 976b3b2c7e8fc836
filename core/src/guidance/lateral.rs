//! Lateral logic: the sign of the bank, with bank reversals when the crossrange to the target
//! leaves a deadband that narrows with speed.
//!
//! The bank-magnitude laws control range only; the sign is chosen by this logic, as in Apollo
//! and MSL (Mendeck & Craig, AIAA 2011-6639, §III "lateral logic": a crossrange corridor as a
//! function of velocity; a reversal is commanded when the crossrange exceeds the corridor on the
//! side the lift is not pointing to) and in FNPEG (Lu, J. Guid. Control Dyn. 37(4), 2014, which
//! uses the same deadband-and-reversal structure on the heading error). Our corridor is linear
//! in speed between two points (`deadband_low_m` at `speed_low_mps`, `deadband_high_m` at
//! `speed_high_mps`, constant outside); the MSL flight values are not public in the paper and the
//! numbers in our scenarios are our own choice.

use serde::{Deserialize, Serialize};

/// The crossrange corridor (`[guidance.lateral]`).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct LateralConfig {
    /// Crossrange deadband at and above `speed_high_mps` \[m\].
    pub deadband_high_m: f64,
    /// Crossrange deadband at and below `speed_low_mps` \[m\].
    pub deadband_low_m: f64,
    /// Speed of the wide end of the corridor \[m/s\].
    pub speed_high_mps: f64,
    /// Speed of the narrow end of the corridor \[m/s\].
    pub speed_low_mps: f64,
}

impl Default for LateralConfig {
    fn default() -> Self {
        LateralConfig {
            deadband_high_m: 4000.0,
            deadband_low_m: 0.0,
            speed_high_mps: 5000.0,
            speed_low_mps: 600.0,
        }
    }
}

impl LateralConfig {
    /// The deadband at speed `v` \[m\].
    pub fn deadband(&self, v: f64) -> f64 {
        let w =
            ((v - self.speed_low_mps) / (self.speed_high_mps - self.speed_low_mps)).clamp(0.0, 1.0);
        self.deadband_low_m + w * (self.deadband_high_m - self.deadband_low_m)
    }
}

/// The lateral logic's memory: the current bank sign and the number of reversals.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Lateral {
    /// Corridor.
    pub config: LateralConfig,
    /// Current sign (+1: bank right).
    pub sign: f64,
    /// Reversals commanded so far.
    pub reversals: usize,
}

impl Lateral {
    /// Start with the given sign; 0 takes the side of the first crossrange.
    pub fn new(config: LateralConfig, sign: f64) -> Self {
        Lateral {
            config,
            sign,
            reversals: 0,
        }
    }

    /// The bank sign for crossrange `xr_m` (positive: target to the right) at speed `v`: reverse
    /// when the target lies outside the corridor on the side opposite to the lift.
    pub fn sign(&mut self, xr_m: f64, v: f64) -> f64 {
        if self.sign == 0.0 {
            self.sign = if xr_m >= 0.0 { 1.0 } else { -1.0 };
        } else if xr_m.abs() > self.config.deadband(v) && xr_m * self.sign < 0.0 {
            self.sign = -self.sign;
            self.reversals += 1;
        }
        self.sign
    }
}
