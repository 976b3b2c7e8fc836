//! The fully numerical predictor–corrector entry guidance (FNPEG) of Lu, *Entry guidance: a
//! unified method*, J. Guid. Control Dyn. 37(4), 2014.
//!
//! The bank magnitude is a linear function of the energy-like variable e = μ/r − v²/2 (Lu §III,
//! the "linear bank profile" parameterisation, with e increasing as the vehicle slows):
//!
//! ```text
//! |σ(e)| = σ0 + (σ_f − σ0) (e − e0) / (e_f − e0)
//! ```
//!
//! e0 the current energy (so σ0 is the magnitude commanded now) and e_f, σ_f fixed. Each guidance
//! cycle the predictor integrates the onboard longitudinal model ([`super::longitudinal`]) from
//! the navigated state to the deployment trigger with this profile, and the corrector solves
//! z(σ0) = R_flown(σ0) − R_togo = 0 for σ0 by the secant method (Lu §III.B, there as Newton's
//! method with a secant derivative), started from the last cycle's σ0. Our choices, not Lu's: the
//! prediction ends at the deployment trigger (speed or dynamic pressure) rather than at e_f, e_f
//! is the energy at the reference trajectory's trigger, the predictor is planar (downrange only;
//! the lateral logic keeps the crossrange small), and a fading-memory density scale
//! κ ← κ + β (D_sensed/D_model − κ) corrects the onboard atmosphere (the density-ratio filter of
//! the predictor–corrector literature, Lu 2014 §V; β is ours).

use super::algorithm::Guidance;
use super::error::GuidanceError;
use super::lateral::Lateral;
use super::limits::BankLimits;
use super::longitudinal::{LongModel, R, Trigger, V};
use super::nav_state::NavState;
use super::target::{Target, range_crossrange};
use crate::atmosphere::Atmosphere;
use crate::dynamics::EntryModel;
use nalgebra::SVector;
use serde::{Deserialize, Serialize};

/// `[guidance.fnpeg]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct FnpegConfig {
    /// Bank magnitude σ_f at the final energy \[deg\].
    #[serde(default = "default_final_bank")]
    pub final_bank_deg: f64,
    /// Predictor RK4 step \[s\].
    #[serde(default = "default_step")]
    pub predictor_step_s: f64,
    /// Secant iterations per cycle.
    #[serde(default = "default_iterations")]
    pub iterations: usize,
    /// Gain β of the density-scale filter (0: trust the onboard atmosphere).
    #[serde(default = "default_beta")]
    pub density_gain: f64,
    /// Below this speed σ0 is no longer corrected \[m/s\].
    #[serde(default = "default_hold")]
    pub hold_speed_mps: f64,
}

fn default_final_bank() -> f64 {
    60.0
}
fn default_step() -> f64 {
    0.5
}
fn default_iterations() -> usize {
    4
}
fn default_beta() -> f64 {
    0.2
}
fn default_hold() -> f64 {
    600.0
}

impl Default for FnpegConfig {
    fn default() -> Self {
        FnpegConfig {
            final_bank_deg: default_final_bank(),
            predictor_step_s: default_step(),
            iterations: default_iterations(),
            density_gain: default_beta(),
            hold_speed_mps: default_hold(),
        }
    }
}

/// FNPEG guidance with the onboard model.
#[derive(Debug, Clone)]
pub struct Fnpeg<A> {
    /// Settings.
    pub config: FnpegConfig,
    /// The onboard entry model.
    pub model: EntryModel<A>,
    /// Deployment trigger.
    pub trigger: Trigger,
    /// Target.
    pub target: Target,
    /// Energy e_f at which |σ| = σ_f \[J/kg\].
    pub final_energy: f64,
    /// Bank magnitude limits.
    pub limits: BankLimits,
    /// Lateral logic.
    pub lateral: Lateral,
    /// Current profile parameter σ0 \[rad\].
    pub sigma0: f64,
    /// Density scale κ estimated from the sensed drag.
    pub density_scale: f64,
    /// Predictions integrated so far.
    pub predictions: usize,
    /// Energy e0 of the last correction, where |σ| = σ0 \[J/kg\].
    pub anchor_energy: f64,
    /// Integration limit of one prediction \[s\].
    pub max_time_s: f64,
}

impl<A: Atmosphere + Clone> Fnpeg<A> {
    /// Energy-like variable e = μ/r − v²/2 \[J/kg\].
    pub fn energy(&self, r: f64, v: f64) -> f64 {
        self.model.planet.mu / r - 0.5 * v * v
    }

    /// The bank magnitude of the profile with parameter σ0 at energy e, from current energy e0.
    pub fn profile(&self, sigma0: f64, e0: f64, e: f64) -> f64 {
        let sf = self.config.final_bank_deg.to_radians();
        let w = if self.final_energy > e0 {
            ((e - e0) / (self.final_energy - e0)).clamp(0.0, 1.0)
        } else {
            1.0
        };
        self.limits.clamp_magnitude(sigma0 + w * (sf - sigma0))
    }

    /// The predicted downrange miss z(σ0) = R_flown − R_togo \[m\] from `nav`.
    pub fn miss(&mut self, nav: &NavState, sigma0: f64) -> f64 {
        let [r, _, _, v, fpa, _] = nav.spherical;
        let lm = LongModel {
            model: &self.model,
            density_scale: self.density_scale,
            trigger: self.trigger,
        };
        let e0 = self.energy(r, v);
        let ld = self.model.vehicle.lift_to_drag;
        let x0 = SVector::from([0.0, r, v, fpa, 0.0]);
        let this = &*self;
        let (xf, _) = lm.fly_to_trigger(&x0, self.config.predictor_step_s, self.max_time_s, |x| {
            ld * this.profile(sigma0, e0, this.energy(x[R], x[V])).cos()
        });
        self.predictions += 1;
        let (d, _) = range_crossrange(nav, &self.target);
        self.model.planet.radius * (xf[0] - d)
    }

    /// Secant iterations on z(σ0) = 0 from the current σ0.
    fn correct(&mut self, nav: &NavState) {
        let (lo, hi) = (self.limits.min_magnitude, self.limits.max_magnitude);
        let mut a = self.sigma0;
        let mut za = self.miss(nav, a);
        let mut b = if a + 0.05 <= hi { a + 0.05 } else { a - 0.05 };
        for _ in 0..self.config.iterations {
            let zb = self.miss(nav, b);
            if zb.abs() < 1.0 || zb == za {
                break;
            }
            let next = (b - zb * (b - a) / (zb - za)).clamp(lo, hi);
            (a, za) = (b, zb);
            b = next;
            if (b - a).abs() < 1e-6 {
                break;
            }
        }
        if b.is_finite() {
            self.sigma0 = b;
        }
    }
}

impl<A: Atmosphere + Clone> Guidance for Fnpeg<A> {
    fn command(&mut self, nav: &NavState) -> Result<f64, GuidanceError> {
        let [r, _, _, v, _, _] = nav.spherical;
        if !(v > 0.0 && r > 0.0 && nav.drag_mps2.is_finite()) {
            return Err(GuidanceError::BadNavigation {
                t_s: nav.t,
                what: "speed or radius not positive, or drag not finite",
            });
        }
        let lm = LongModel {
            model: &self.model,
            density_scale: 1.0,
            trigger: self.trigger,
        };
        let modelled = lm.drag(r, v);
        // Update κ only where the drag is measurable (above 0.05 Earth g).
        if modelled > 0.0 && nav.drag_mps2 > 0.05 * crate::planet::G_EARTH {
            let ratio = nav.drag_mps2 / modelled;
            self.density_scale += self.config.density_gain * (ratio - self.density_scale);
        }
        let e = self.energy(r, v);
        if v >= self.config.hold_speed_mps {
            self.correct(nav);
            self.anchor_energy = e;
        }
        // Past the hold speed the last profile is flown, no longer corrected.
        let magnitude = self.profile(self.sigma0, self.anchor_energy, e);
        let (_, xr) = range_crossrange(nav, &self.target);
        let sign = self.lateral.sign(self.model.planet.radius * xr, v);
        Ok(sign * magnitude)
    }

    fn name(&self) -> &'static str {
        "fnpeg"
    }
}
