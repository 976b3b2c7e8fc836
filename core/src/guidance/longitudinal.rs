//! The onboard longitudinal (planar) entry model every guidance algorithm predicts with, and the
//! deployment trigger.
//!
//! State `x = [θ, r, v, γ, u]`: downrange angle θ \[rad\] along the great circle of the initial
//! heading, radius r \[m\], planet-relative speed v \[m/s\], flight-path angle γ \[rad\] and the
//! vertical lift-to-drag ratio u = (L/D) cos σ, carried as a constant state (u̇ = 0) so that the
//! adjoint of the same equations gives the control sensitivity (Apollo's ∂R/∂(L/D)). The equations
//! are the in-plane rows of the spherical 3-DOF model of seed 000 eq. 1 / seed 001 eq. 9–11 with
//! ψ̇ = 0 (non-rotating planet, no heading change):
//!
//! ```text
//! θ̇ = v cosγ / r,  ṙ = v sinγ,  v̇ = −D − g sinγ,  γ̇ = (D u − g cosγ)/v + (v/r) cosγ,  u̇ = 0
//! ```
//!
//! with g = μ/r² and D = ½ κ ρ(r − R) v² C_D S/m, κ the guidance's density scale (1: the onboard
//! model itself; the predictor–corrector estimates it from the sensed drag).

use super::deploy::RangeTrigger;
use crate::atmosphere::Atmosphere;
use crate::dynamics::EntryModel;
use crate::dynamics::rk4_step_generic;
use crate::math::Real;
use nalgebra::SVector;
use serde::{Deserialize, Serialize};

/// The longitudinal state `[θ, r, v, γ, u]`.
pub type LongState<T> = SVector<T, 5>;

/// Index of θ, r, v, γ, u in [`LongState`].
pub const THETA: usize = 0;
/// Index of r.
pub const R: usize = 1;
/// Index of v.
pub const V: usize = 2;
/// Index of γ.
pub const GAMMA: usize = 3;
/// Index of u.
pub const U: usize = 4;

/// The deployment trigger that ends guided flight (parachute deployment).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case", deny_unknown_fields)]
pub enum Trigger {
    /// Planet-relative speed falls to this value \[m/s\].
    SpeedMps(f64),
    /// Dynamic pressure ½ρv² falls to this value \[Pa\] after having exceeded it.
    DynamicPressurePa(f64),
    /// The Mars 2020 range trigger ([`RangeTrigger`]): deploy where the range-to-go reaches
    /// zero inside the deployment box, with a speed backstop. Onboard predictions end at its
    /// nominal speed.
    Range(RangeTrigger),
}

impl Trigger {
    /// The trigger function c of onboard predictions: positive before deployment, zero at
    /// deployment (for the range trigger: at its nominal speed; the deployment itself is
    /// decided by [`RangeTrigger::function`]).
    pub fn function<T: Real>(&self, density: T, v: T) -> T {
        match *self {
            Trigger::SpeedMps(vf) => v - vf,
            Trigger::DynamicPressurePa(qf) => density * v * v * 0.5 - qf,
            Trigger::Range(rt) => v - rt.nominal_speed_mps,
        }
    }
}

/// The onboard model guidance predicts with: the onboard [`EntryModel`]'s planet, atmosphere
/// and vehicle, a density scale κ, and the trigger.
#[derive(Debug, Clone)]
pub struct LongModel<'a, A> {
    /// The onboard entry model (the filter's, never the truth's).
    pub model: &'a EntryModel<A>,
    /// Density scale κ on the onboard atmosphere.
    pub density_scale: f64,
    /// Deployment trigger.
    pub trigger: Trigger,
}

impl<A: Atmosphere> LongModel<'_, A> {
    /// Onboard density at radius r.
    pub fn density<T: Real>(&self, r: T) -> T {
        self.model.atmosphere.density(r - self.model.planet.radius)
            * (self.density_scale * self.model.density_factor)
    }

    /// Drag acceleration D \[m/s²\] at radius r and speed v.
    pub fn drag<T: Real>(&self, r: T, v: T) -> T {
        self.density(r) * v * v * (0.5 * self.model.vehicle.cd_s_over_m)
    }

    /// ẋ of the longitudinal state (module documentation).
    pub fn rhs<T: Real>(&self, x: &LongState<T>) -> LongState<T> {
        let (r, v, g_, u) = (x[R], x[V], x[GAMMA], x[U]);
        let g = r.powi(2).recip() * self.model.planet.mu;
        let d = self.drag(r, v);
        let (sg, cg) = (g_.sin(), g_.cos());
        SVector::from([
            v * cg / r,
            v * sg,
            -d - g * sg,
            (d * u - g * cg) / v + v / r * cg,
            T::from(0.0),
        ])
    }

    /// The trigger function at x (positive before deployment).
    pub fn trigger_fn<T: Real>(&self, x: &LongState<T>) -> T {
        self.trigger.function(self.density(x[R]), x[V])
    }

    /// One RK4 step of length h in any scalar type.
    pub fn step<T: Real>(&self, x: &LongState<T>, h: f64) -> LongState<T> {
        rk4_step_generic(|y| self.rhs(y), x, h)
    }

    /// The step length h* ∈ (0, h\] from x at which the trigger function crosses zero, by Newton
    /// iteration on c(Φ_h*(x)) with dc/dh* = ∇c·f (h is the step in which it crossed).
    pub fn crossing_step(&self, x: &LongState<f64>, h: f64) -> f64 {
        let c0 = self.trigger_fn(x);
        let c1 = self.trigger_fn(&self.step(x, h));
        // Secant start, then Newton.
        let mut hs = (h * c0 / (c0 - c1)).clamp(0.0, h);
        for _ in 0..8 {
            let xs = self.step(x, hs);
            let c = self.trigger_fn(&xs);
            let (_, grad) =
                crate::math::ad_jacobian(|y| SVector::<_, 1>::from([self.trigger_fn(&y)]), &xs);
            let cdot = (grad * self.rhs(&xs))[0];
            if cdot == 0.0 || !cdot.is_finite() {
                break;
            }
            let dh = -c / cdot;
            hs = (hs + dh).clamp(0.0, h);
            if dh.abs() < 1e-12 {
                break;
            }
        }
        hs
    }

    /// Fly x with the vertical L/D given by `u_of(x)` (re-evaluated each step) until the
    /// trigger, an altitude ≤ 0, or `max_time` s; step h. Returns the final state and whether the
    /// trigger was met. The trigger fires when c goes from > 0 to ≤ 0 (c ≤ 0 at the start arms it
    /// later, for a dynamic-pressure trigger before the pressure has risen).
    pub fn fly_to_trigger(
        &self,
        x0: &LongState<f64>,
        h: f64,
        max_time: f64,
        mut u_of: impl FnMut(&LongState<f64>) -> f64,
    ) -> (LongState<f64>, bool) {
        let mut x = *x0;
        let mut armed = self.trigger_fn(&x) > 0.0;
        let mut t = 0.0;
        while t < max_time {
            x[U] = u_of(&x);
            let next = self.step(&x, h);
            if !next.iter().all(|v| v.is_finite()) || next[R] <= self.model.planet.radius {
                return (x, false);
            }
            let c = self.trigger_fn(&next);
            if armed && c <= 0.0 {
                let hs = self.crossing_step(&x, h);
                return (self.step(&x, hs), true);
            }
            armed |= c > 0.0;
            x = next;
            t += h;
        }
        (x, false)
    }
}
