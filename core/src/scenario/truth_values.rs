//! The truth's values of the parameters a filter may carry as augmented or consider states, raw
//! and truth-equivalent.
//!
//! A filter state can stand for something other than the truth parameter of the same name. Drag
//! is ½ρv²·C_D S/m, so a filter that estimates the density (ρ0 or Δ) but holds C_D S/m fixed at a
//! wrong value converges to the density that reproduces the true drag, ρ·B_true/B_filter with
//! B = C_D S/m (seed 000 §4: the filter's C_D S/m is 10 % off and ρ0 absorbs it). Judging such a
//! filter against the raw ρ0 calls a correct filter inconsistent. The *truth-equivalent* value is
//! the value of the filter's parameter for which its model reproduces the truth exactly, where one
//! exists:
//!
//! | state | raw truth | truth-equivalent |
//! |---|---|---|
//! | ρ0 | ρ0_true·(1 + Δ_true) (exponential truth) | raw · B_true/B_filter if C_D S/m is not a filter state |
//! | Δ | Δ_true | (1 + Δ_true)·B_true/B_filter − 1 if C_D S/m is not a state; only when the filter's atmosphere is the truth's mean model |
//! | C_D S/m | B_true | B_true·(1 + Δ_true) if the filter has no density state and the truth's mean atmosphere |
//! | L/D | (L/D)_true | the same |
//! | accelerometer bias | the sensor's bias on that axis | the same |
//!
//! `None` means the truth has no such value (ρ0 of a tabulated truth atmosphere, Δ when the
//! filter's atmosphere is not the truth's mean model).

use super::build::Scenario;
use super::draw::TruthDraw;
use crate::dynamics::AugmentedParam;

impl Scenario {
    /// The truth's raw value of parameter `a` in the realisation `draw`.
    pub fn truth_parameter(&self, draw: &TruthDraw, a: AugmentedParam) -> Option<f64> {
        let tm = &draw.model;
        match a {
            AugmentedParam::Rho0 => self
                .config
                .truth
                .atmosphere
                .reference_density()
                .map(|r| r * tm.density_factor),
            AugmentedParam::LiftToDrag => Some(tm.vehicle.lift_to_drag),
            AugmentedParam::CdSOverM => Some(tm.vehicle.cd_s_over_m),
            AugmentedParam::DensityBias => Some(tm.density_factor - 1.0),
            AugmentedParam::AccelBiasX
            | AugmentedParam::AccelBiasY
            | AugmentedParam::AccelBiasZ => {
                let axis = a.accel_axis()? as usize;
                self.config
                    .sensors
                    .imu
                    .as_ref()
                    .map(|imu| imu.bias_mps2[axis])
            }
        }
    }

    /// The truth-equivalent value of the filter's parameter `a` in the realisation `draw` (see
    /// the module documentation).
    pub fn truth_equivalent(&self, draw: &TruthDraw, a: AugmentedParam) -> Option<f64> {
        let raw = self.truth_parameter(draw, a)?;
        let fm = self.filter_model();
        let has = |p: AugmentedParam| fm.augmented.contains(&p);
        let b_ratio = if has(AugmentedParam::CdSOverM) {
            1.0
        } else {
            draw.model.vehicle.cd_s_over_m / fm.vehicle.cd_s_over_m
        };
        let same_atmosphere = self.config.filter.atmosphere == self.config.truth.atmosphere;
        match a {
            AugmentedParam::Rho0 => Some(raw * b_ratio),
            AugmentedParam::DensityBias => same_atmosphere.then_some((1.0 + raw) * b_ratio - 1.0),
            AugmentedParam::CdSOverM => {
                let density_state = has(AugmentedParam::Rho0) || has(AugmentedParam::DensityBias);
                Some(if !density_state && same_atmosphere {
                    raw * draw.model.density_factor
                } else {
                    raw
                })
            }
            _ => Some(raw),
        }
    }
}
