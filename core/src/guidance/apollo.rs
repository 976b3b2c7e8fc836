//! Apollo final-phase entry guidance as adapted for the Mars Science Laboratory.
//!
//! Mendeck & Craig, *Entry guidance for the 2011 Mars Science Laboratory mission*, AIAA
//! 2011-6639, §III (the "final phase" / range-control phase, after Apollo's final phase, Moseley
//! 1969). Against the reference trajectory ([`super::reference`]) at the current speed v:
//!
//! ```text
//! R_p = R_ref(v) + F1(v) (D − D_ref(v)) + F2(v) (ṙ − ṙ_ref(v))           predicted range
//! (L/D)_c = (L/D)_ref + K3 (R − R_p) / F3(v)                             vertical L/D command
//! |σ| = acos( (L/D)_c / (L/D) )                                          bank magnitude
//! ```
//!
//! with R the range-to-go to the target (great-circle arc), D the sensed drag, ṙ the navigated
//! altitude rate, (L/D)_ref = (L/D) cos σ_ref and K3 the overcontrol gain (the issue gives MSL's
//! as 5; our default, changeable in `[guidance.apollo]`). Apollo's F3 term of the drag-derivative
//! (F3 in some write-ups multiplies the L/D error itself) is the one used here, ∂R/∂(L/D). The
//! bank sign comes from the lateral logic ([`super::lateral`]).
//!
//! Phases (Mendeck & Craig §III, simplified): before the sensed drag reaches
//! `start_drag_mps2` the reference bank is flown (MSL's pre-entry and pre-bank phases); from
//! then on range is controlled until the speed falls below `hold_speed_mps`, where the gains
//! (F3 → 0 at the trigger) stop being useful and the last bank magnitude is held with the
//! lateral logic still active. With `heading_alignment_speed_mps` set, MSL's last phase replaces
//! the hold below that speed: **heading alignment** (Mendeck & Craig §III: range is no longer
//! controlled; the bank steers the velocity toward the target). Our law: with Δψ = β − ψ the
//! bearing of the target minus the heading (positive: target to the right),
//!
//! ```text
//! σ = clamp(K_ha Δψ, −σ_ha, σ_ha)
//! ```
//!
//! (positive bank = lift to the right), K_ha `heading_alignment_gain` and σ_ha
//! `heading_alignment_max_bank_deg`: near lift-up, so the vehicle also keeps its altitude. The
//! proportional form and its two constants are our choice; the paper does not print MSL's.

use super::algorithm::Guidance;
use super::error::GuidanceError;
use super::lateral::Lateral;
use super::limits::BankLimits;
use super::nav_state::NavState;
use super::reference::ReferenceTrajectory;
use super::target::{Target, bearing, range_crossrange};
use serde::{Deserialize, Serialize};

/// `[guidance.apollo]`.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ApolloConfig {
    /// Overcontrol gain K3 on the range error.
    #[serde(default = "default_gain")]
    pub overcontrol_gain: f64,
    /// Range control starts when the sensed drag first exceeds this \[m/s²\].
    #[serde(default = "default_start_drag")]
    pub start_drag_mps2: f64,
    /// Below this speed the bank magnitude is held \[m/s\].
    #[serde(default = "default_hold_speed")]
    pub hold_speed_mps: f64,
    /// Heading alignment (module documentation) below this speed \[m/s\], in place of the
    /// hold; absent: no heading alignment.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub heading_alignment_speed_mps: Option<f64>,
    /// Heading alignment's gain K_ha \[deg of bank per deg of heading error\].
    #[serde(default = "default_ha_gain")]
    pub heading_alignment_gain: f64,
    /// Heading alignment's largest bank magnitude σ_ha \[deg\].
    #[serde(default = "default_ha_bank")]
    pub heading_alignment_max_bank_deg: f64,
}

fn default_gain() -> f64 {
    5.0
}
fn default_start_drag() -> f64 {
    // 0.2 Earth g: our choice (MSL starts range control on a sensed-drag threshold; we have not
    // checked its value against Mendeck & Craig).
    0.2 * crate::planet::G_EARTH
}
fn default_hold_speed() -> f64 {
    800.0
}
fn default_ha_gain() -> f64 {
    30.0
}
fn default_ha_bank() -> f64 {
    30.0
}

impl Default for ApolloConfig {
    fn default() -> Self {
        ApolloConfig {
            overcontrol_gain: default_gain(),
            start_drag_mps2: default_start_drag(),
            hold_speed_mps: default_hold_speed(),
            heading_alignment_speed_mps: None,
            heading_alignment_gain: default_ha_gain(),
            heading_alignment_max_bank_deg: default_ha_bank(),
        }
    }
}

/// Apollo final-phase guidance on a reference trajectory.
#[derive(Debug, Clone)]
pub struct ApolloGuidance {
    /// Settings.
    pub config: ApolloConfig,
    /// Reference trajectory with its gains.
    pub reference: ReferenceTrajectory,
    /// Target.
    pub target: Target,
    /// Vehicle L/D (onboard value).
    pub lift_to_drag: f64,
    /// Planet radius for arc lengths \[m\].
    pub radius: f64,
    /// Bank magnitude limits.
    pub limits: BankLimits,
    /// Lateral logic.
    pub lateral: Lateral,
    started: bool,
    magnitude: f64,
}

impl ApolloGuidance {
    /// Guidance to `target` on `reference`.
    pub fn new(
        config: ApolloConfig,
        reference: ReferenceTrajectory,
        target: Target,
        lift_to_drag: f64,
        radius: f64,
        limits: BankLimits,
        lateral: Lateral,
    ) -> Self {
        let magnitude = limits.clamp_magnitude(reference.bank.abs());
        ApolloGuidance {
            config,
            reference,
            target,
            lift_to_drag,
            radius,
            limits,
            lateral,
            started: false,
            magnitude,
        }
    }

    /// The predicted range R_p and the vertical L/D command at `nav` (no phase logic, no limits).
    pub fn law(&self, nav: &NavState) -> (f64, f64) {
        let v = nav.speed();
        let p = self.reference.at_speed(v);
        let (d, _) = range_crossrange(nav, &self.target);
        let range = self.radius * d;
        let predicted =
            p.range_to_go + p.f1 * (nav.drag_mps2 - p.drag) + p.f2 * (nav.rdot() - p.rdot);
        let ld =
            self.reference.vertical_ld + self.config.overcontrol_gain * (range - predicted) / p.f3;
        (predicted, ld)
    }

    /// The heading-alignment bank at `nav` (module documentation) \[rad\].
    pub fn heading_alignment(&self, nav: &NavState) -> f64 {
        let [_, lon, lat, _, _, psi] = nav.spherical;
        let beta = bearing(lat, lon, self.target.lat, self.target.lon);
        let err = (beta - psi).sin().atan2((beta - psi).cos());
        let max = self.config.heading_alignment_max_bank_deg.to_radians();
        let sigma = (self.config.heading_alignment_gain * err).clamp(-max, max);
        sigma.signum() * self.limits.clamp_magnitude(sigma.abs())
    }
}

impl Guidance for ApolloGuidance {
    fn command(&mut self, nav: &NavState) -> Result<f64, GuidanceError> {
        let v = nav.speed();
        if !(v > 0.0 && nav.drag_mps2.is_finite()) {
            return Err(GuidanceError::BadNavigation {
                t_s: nav.t,
                what: "speed not positive or drag not finite",
            });
        }
        self.started |= nav.drag_mps2 >= self.config.start_drag_mps2;
        if let Some(v_ha) = self.config.heading_alignment_speed_mps
            && self.started
            && v < v_ha
        {
            return Ok(self.heading_alignment(nav));
        }
        if self.started && v >= self.config.hold_speed_mps {
            let (_, ld) = self.law(nav);
            let c = (ld / self.lift_to_drag).clamp(-1.0, 1.0);
            self.magnitude = self.limits.clamp_magnitude(c.acos());
        }
        let (_, xr) = range_crossrange(nav, &self.target);
        let sign = self.lateral.sign(self.radius * xr, v);
        Ok(sign * self.magnitude)
    }

    fn name(&self) -> &'static str {
        "apollo"
    }
}
