//! Altitude safeguard: altitude has priority over range.
//!
//! Both range-control laws spend lift on range: a vehicle that is long banks steeper, sinks, and
//! on the dispersed MSL entry a few percent of runs reach the ground still above the deployment
//! speed (docs/guidance.md). A parachute deployment needs altitude — MSL's entry requirement was
//! a deployment altitude floor, met by design margin rather than by the range law (Mendeck &
//! Craig, AIAA 2011-6639, §II) — and predictor–corrector guidance handles such terminal
//! constraints by giving the altitude constraint priority over the range target (Lu, J. Guid.
//! Control Dyn. 37(4), 2014, which enforces path and terminal constraints around the range
//! solution rather than trading them against it).
//!
//! Ours wraps either algorithm (`[guidance] min_deploy_altitude_m`) as a safety filter on its
//! bank magnitude |σ_c|. Each cycle, once the speed is below the reference's speed at peak drag,
//! the onboard longitudinal model ([`super::longitudinal`]) predicts from the navigated state an
//! *escape*: |σ_c| flown for a horizon (one guidance period, the roll from |σ_c| to
//! `bank_min_deg` at the rate limit, and the time to reach that rate at the acceleration limit),
//! then the most lift (`bank_min_deg`) to the trigger. If the escape reaches the trigger at or
//! above the floor h_min, σ_c is flown unchanged: the vehicle can still afford it. Otherwise the
//! magnitude is capped at the largest one whose escape does (bisection between `bank_min_deg`
//! and |σ_c|: more bank over the horizon, a lower trajectory), or `bank_min_deg` when even an
//! immediate escape falls short. The sign (the lateral logic's) is kept. So the range law flies
//! freely until the floor is about to become unreachable, and altitude wins from there.
//!
//! Before peak drag the safeguard does not act: there a bank nearer lift-up need not mean a
//! higher deployment (on the dispersed MSL entry, lift-up from 6 km/s lofts the vehicle to 30 km
//! and it deploys *lower*, or not within the flight time — measured, docs/guidance.md), so the
//! monotonicity the bisection needs does not hold.
//!
//! Only onboard quantities are used: the estimate, the onboard vehicle constants and atmosphere,
//! and a density scale κ estimated from the sensed drag as FNPEG's (κ ← κ + β (D_sensed/D_model −
//! κ) above 0.05 g, β = [`DENSITY_GAIN`]), which also absorbs a C_D S/m error. An L/D error is
//! not corrected: the floor must carry that margin.

use super::algorithm::Guidance;
use super::error::GuidanceError;
use super::limits::BankLimits;
use super::longitudinal::{LongModel, R, Trigger};
use super::nav_state::NavState;
use crate::atmosphere::Atmosphere;
use crate::dynamics::EntryModel;
use nalgebra::SVector;

/// Gain β of the safeguard's density-scale filter (FNPEG's default; our choice).
pub const DENSITY_GAIN: f64 = 0.2;
/// RK4 step of the safeguard's predictions \[s\] (FNPEG's default predictor step).
pub const PREDICTOR_STEP_S: f64 = 0.5;
/// Bisection iterations on the capped magnitude (180° / 2⁸ ≈ 0.7°).
pub const BISECTIONS: usize = 8;

/// A guidance algorithm whose bank magnitude is capped so that the predicted deployment
/// altitude stays at or above a floor (module documentation).
pub struct AltitudeSafeguard<A> {
    /// The range-control algorithm.
    pub inner: Box<dyn Guidance + Send>,
    /// The onboard entry model (the filter's, never the truth's).
    pub model: EntryModel<A>,
    /// Deployment trigger.
    pub trigger: Trigger,
    /// Floor h_min on the predicted deployment altitude \[m\].
    pub floor_m: f64,
    /// Bank magnitude limits (the cap never goes below `min_magnitude`).
    pub limits: BankLimits,
    /// Density scale κ estimated from the sensed drag.
    pub density_scale: f64,
    /// Integration limit of one prediction \[s\].
    pub max_time_s: f64,
    /// The safeguard acts below this speed \[m/s\]: the reference's speed at peak drag (before
    /// it, lift-up lofts the vehicle and a lower bank need not mean a higher deployment).
    pub active_below_mps: f64,
    /// Guidance period \[s\].
    pub period_s: f64,
    /// Cycles in which the cap reduced the algorithm's magnitude.
    pub activations: usize,
    /// Predictions integrated so far.
    pub predictions: usize,
}

impl<A: Atmosphere> AltitudeSafeguard<A> {
    /// The altitude \[m\] at which the trigger is predicted from `nav` when the bank magnitude
    /// `magnitude` is flown for `horizon_s` seconds and the most lift (`bank_min_deg`) after
    /// that; −∞ when the prediction reaches the ground first.
    pub fn predicted_deploy_altitude(&mut self, nav: &NavState, magnitude: f64) -> f64 {
        let [r, _, _, v, fpa, _] = nav.spherical;
        let lm = LongModel {
            model: &self.model,
            density_scale: self.density_scale,
            trigger: self.trigger,
        };
        let ld = self.model.vehicle.lift_to_drag;
        let (u_now, u_escape) = (ld * magnitude.cos(), ld * self.limits.min_magnitude.cos());
        let x0 = SVector::from([0.0, r, v, fpa, u_now]);
        self.predictions += 1;
        let horizon_steps = (self.horizon_s(magnitude) / PREDICTOR_STEP_S).ceil() as usize;
        let mut steps = 0usize;
        let (xf, met) = lm.fly_to_trigger(&x0, PREDICTOR_STEP_S, self.max_time_s, |_| {
            steps += 1;
            if steps <= horizon_steps {
                u_now
            } else {
                u_escape
            }
        });
        let altitude = xf[R] - self.model.planet.radius;
        // Still above the floor when the integration limit ran out: not a low trajectory.
        if met || altitude > self.floor_m {
            altitude
        } else {
            f64::NEG_INFINITY
        }
    }

    /// How long a bank magnitude is flown before the escape to the most lift can take effect
    /// \[s\]: one guidance period, plus the roll from `magnitude` to `bank_min_deg` at the rate
    /// limit, plus the time to reach the rate limit at the acceleration limit.
    pub fn horizon_s(&self, magnitude: f64) -> f64 {
        let roll = (magnitude - self.limits.min_magnitude).max(0.0);
        self.period_s + roll / self.limits.rate_max + self.limits.rate_max / self.limits.accel_max
    }

    /// The largest bank magnitude ≤ `magnitude` from which the escape still reaches the trigger
    /// at or above the floor (the bank minimum when none does).
    pub fn cap(&mut self, nav: &NavState, magnitude: f64) -> f64 {
        if self.predicted_deploy_altitude(nav, magnitude) >= self.floor_m {
            return magnitude;
        }
        let lo_bank = self.limits.min_magnitude;
        if magnitude <= lo_bank || self.predicted_deploy_altitude(nav, lo_bank) < self.floor_m {
            return lo_bank.min(magnitude);
        }
        // h(lo) ≥ floor > h(hi): keep the invariant and return the feasible end.
        let (mut lo, mut hi) = (lo_bank, magnitude);
        for _ in 0..BISECTIONS {
            let mid = 0.5 * (lo + hi);
            if self.predicted_deploy_altitude(nav, mid) >= self.floor_m {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        lo
    }
}

impl<A: Atmosphere> Guidance for AltitudeSafeguard<A> {
    fn command(&mut self, nav: &NavState) -> Result<f64, GuidanceError> {
        let command = self.inner.command(nav)?;
        let [r, _, _, v, _, _] = nav.spherical;
        let modelled = LongModel {
            model: &self.model,
            density_scale: 1.0,
            trigger: self.trigger,
        }
        .drag(r, v);
        if modelled > 0.0 && nav.drag_mps2 > 0.05 * crate::planet::G_EARTH {
            let ratio = nav.drag_mps2 / modelled;
            self.density_scale += DENSITY_GAIN * (ratio - self.density_scale);
        }
        let magnitude = command.abs();
        if v > self.active_below_mps {
            return Ok(command);
        }
        let capped = self.cap(nav, magnitude);
        if capped < magnitude {
            self.activations += 1;
        }
        let sign = if command < 0.0 { -1.0 } else { 1.0 };
        Ok(sign * capped)
    }

    fn name(&self) -> &'static str {
        self.inner.name()
    }
}
