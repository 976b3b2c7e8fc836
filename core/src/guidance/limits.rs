//! Bank-angle limits: magnitude bounds on the command, rate and acceleration limits on the bank
//! the vehicle flies.
//!
//! The attitude control system cannot follow a bank step: MSL's guidance limits the commanded
//! bank rate and acceleration (Mendeck & Craig, AIAA 2011-6639, §III: the bank command is passed
//! through rate and acceleration limits, and reversals are flown at the limits). Our limiter is a
//! second-order bang–bang follower: the bank rate heads for
//!
//! ```text
//! ω_des = sign(e) · min(ω_max, sqrt(2 a_max |e|)),  e = σ_cmd − σ
//! ```
//!
//! (the fastest rate from which the bank can still stop at the command with deceleration a_max),
//! changing by at most a_max·Δt per step and never exceeding ω_max. The bank is a signed angle on
//! (−180°, 180°\] and moves along it, so a reversal between ±σ (σ < 90°) passes through lift-up
//! (σ = 0), the shorter way. The rate bound holds at every step by construction (tested); the
//! acceleration bound holds except at the step where the bank reaches the command, where the rate
//! snaps to zero (from at most sqrt(2 a_max |e|) + a_max·Δt).

use super::error::GuidanceError;
use serde::{Deserialize, Serialize};

/// Bank limits (`[guidance]` fields `bank_min_deg` … `bank_accel_limit_deg_s2`), in radians.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct BankLimits {
    /// Smallest bank magnitude commanded \[rad\].
    pub min_magnitude: f64,
    /// Largest bank magnitude commanded \[rad\].
    pub max_magnitude: f64,
    /// Bank rate limit ω_max \[rad/s\].
    pub rate_max: f64,
    /// Bank acceleration limit a_max \[rad/s²\].
    pub accel_max: f64,
}

impl BankLimits {
    /// Check the limits: 0 ≤ min ≤ max ≤ π, rate and acceleration > 0.
    pub fn checked(self) -> Result<Self, GuidanceError> {
        if !(0.0..=std::f64::consts::PI).contains(&self.min_magnitude) {
            return Err(GuidanceError::Parameter {
                name: "bank_min_deg",
                value: self.min_magnitude.to_degrees(),
                allowed: "must be >= 0 and <= 180 deg",
            });
        }
        if !(self.min_magnitude..=std::f64::consts::PI).contains(&self.max_magnitude) {
            return Err(GuidanceError::Parameter {
                name: "bank_max_deg",
                value: self.max_magnitude.to_degrees(),
                allowed: "must be >= bank_min_deg and <= 180 deg",
            });
        }
        for (name, v) in [
            ("bank_rate_limit_deg_s", self.rate_max),
            ("bank_accel_limit_deg_s2", self.accel_max),
        ] {
            if !(v > 0.0 && v.is_finite()) {
                return Err(GuidanceError::Parameter {
                    name,
                    value: v.to_degrees(),
                    allowed: "must be > 0",
                });
            }
        }
        Ok(self)
    }

    /// A bank magnitude clamped to \[min, max\].
    pub fn clamp_magnitude(&self, magnitude: f64) -> f64 {
        magnitude.clamp(self.min_magnitude, self.max_magnitude)
    }
}

/// The bank the vehicle flies: angle and rate, advanced towards the command within the limits.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct BankActuator {
    /// Limits.
    pub limits: BankLimits,
    /// Current bank \[rad\].
    pub bank: f64,
    /// Current bank rate \[rad/s\].
    pub rate: f64,
}

impl BankActuator {
    /// At rest at `bank`.
    pub fn new(limits: BankLimits, bank: f64) -> Self {
        BankActuator {
            limits,
            bank,
            rate: 0.0,
        }
    }

    /// Advance `dt` seconds towards the signed command `command` \[rad\]; returns the new bank.
    pub fn step(&mut self, command: f64, dt: f64) -> f64 {
        let (w, a) = (self.limits.rate_max, self.limits.accel_max);
        let e = command - self.bank;
        let desired = e.signum() * w.min((2.0 * a * e.abs()).sqrt());
        let mut rate = self.rate + (desired - self.rate).clamp(-a * dt, a * dt);
        rate = rate.clamp(-w, w);
        if rate * e > 0.0 && (rate * dt).abs() >= e.abs() {
            // Reaches the command within this step: stop there.
            self.bank = command;
            self.rate = 0.0;
        } else {
            self.bank += rate * dt;
            self.rate = rate;
        }
        self.bank
    }
}
