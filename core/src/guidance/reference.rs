//! The reference trajectory of Apollo final-phase guidance and its adjoint sensitivities.
//!
//! The nominal entry is flown at a constant reference bank σ_ref with the onboard longitudinal
//! model ([`super::longitudinal`]) to the deployment trigger; drag D_ref, altitude rate ṙ_ref and
//! range-to-go R_ref are tabulated against speed (Mendeck & Craig, *Entry guidance for the 2011
//! Mars Science Laboratory mission*, AIAA 2011-6639, §III "final phase": the reference profiles
//! of the Apollo final-phase algorithm are functions of relative velocity).
//!
//! **Gains from the adjoint.** Let θ_f be the downrange angle at the trigger and λ(t) = ∂θ_f/∂x(t)
//! its influence coefficients along the reference (the Apollo "influence coefficients", Mendeck &
//! Craig §III; Moseley, *The Apollo entry guidance: a review of the mathematical development and
//! its operational characteristics*, TRW 1969). They solve the adjoint equation λ̇ = −Aᵀλ with
//! A = ∂f/∂x of the longitudinal model. The trajectory ends where the trigger function c(x) = 0,
//! so perturbing the final state also moves the end time by δt_f = −∇c·δx/ċ:
//!
//! ```text
//! λ(t_f) = e_θ − (θ̇_f / ċ_f) ∇c(x_f)
//! ```
//!
//! We propagate the *discrete* adjoint of the RK4 reference: λ_k = Φ_kᵀ λ_{k+1} with Φ_k the exact
//! Jacobian of the RK4 step (forward-mode AD), and the last, partial step to the trigger
//! differentiated with its length h*(x). Along the reference λᵀf = 0 (λᵀf is constant for an
//! autonomous system and zero at t_f), so a time shift leaves θ_f unchanged and λ compares a
//! flown state with the reference *at the same speed*: with δv = 0,
//!
//! ```text
//! δR_togo = R (λ_r δr + λ_γ δγ),  δD = (∂D/∂r) δr,  δṙ = v cosγ δγ
//! F1 = ∂R/∂D = R λ_r / (∂D/∂r),  F2 = ∂R/∂ṙ = R λ_γ / (v cosγ),  F3 = ∂R/∂(L/D) = R λ_u
//! ```
//!
//! (R the planet radius, ranges in metres of surface arc). λ_u is the sensitivity to a constant
//! change of the vertical L/D from t to the end (u is a state with u̇ = 0, λ_u(t_f) = 0), which is
//! Apollo's ∂R/∂(L/D). ∂D/∂r is taken by AD through the onboard atmosphere. The tests check
//! F1–F3 against finite differences of re-flown reference trajectories.

use super::error::GuidanceError;
use super::longitudinal::{GAMMA, LongModel, LongState, R, THETA, U, V};
use crate::atmosphere::Atmosphere;
use crate::math::ad_jacobian;
use nalgebra::{SMatrix, SVector};

/// One tabulated point of the reference.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReferencePoint {
    /// Time since the start \[s\].
    pub t: f64,
    /// Longitudinal state `[θ, r, v, γ, u]`.
    pub x: [f64; 5],
    /// Drag acceleration D_ref \[m/s²\].
    pub drag: f64,
    /// Altitude rate ṙ_ref \[m/s\].
    pub rdot: f64,
    /// Range-to-go R_ref \[m\] (surface arc to the reference landing point).
    pub range_to_go: f64,
    /// Influence coefficients λ = ∂θ_f/∂x (per unit of each state).
    pub lambda: [f64; 5],
    /// F1 = ∂R/∂D \[m/(m/s²)\].
    pub f1: f64,
    /// F2 = ∂R/∂ṙ \[m/(m/s)\].
    pub f2: f64,
    /// F3 = ∂R/∂(L/D) \[m\].
    pub f3: f64,
}

/// The reference trajectory: points from peak speed to the trigger, speed decreasing.
#[derive(Debug, Clone, PartialEq)]
pub struct ReferenceTrajectory {
    /// Reference bank \[rad\].
    pub bank: f64,
    /// Vertical L/D of the reference, (L/D) cos σ_ref.
    pub vertical_ld: f64,
    /// Downrange angle flown to the trigger \[rad\].
    pub theta_final: f64,
    /// Final longitudinal state at the trigger.
    pub final_state: [f64; 5],
    /// Tabulated points, speed strictly decreasing.
    pub points: Vec<ReferencePoint>,
}

/// Settings of the reference computation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ReferenceSettings {
    /// Constant reference bank \[rad\].
    pub bank: f64,
    /// Integration step \[s\].
    pub step_s: f64,
    /// Give up after this time \[s\].
    pub max_time_s: f64,
}

impl ReferenceTrajectory {
    /// Fly the nominal entry `x0` (`[r, v, γ]` of the entry state; θ = 0) at the reference bank
    /// with `model`, tabulate and compute the adjoint gains.
    pub fn build<A: Atmosphere>(
        model: &LongModel<'_, A>,
        r0: f64,
        v0: f64,
        fpa0: f64,
        s: &ReferenceSettings,
    ) -> Result<Self, GuidanceError> {
        let u = model.model.vehicle.lift_to_drag * s.bank.cos();
        let h = s.step_s;
        let mut x: LongState<f64> = SVector::from([0.0, r0, v0, fpa0, u]);
        let mut states = vec![x];
        let mut stms: Vec<SMatrix<f64, 5, 5>> = Vec::new();
        let mut armed = model.trigger_fn(&x) > 0.0;
        let max_steps = (s.max_time_s / h).ceil() as usize;
        let mut last = None;
        for _ in 0..max_steps {
            let next = model.step(&x, h);
            if !next.iter().all(|v| v.is_finite()) || next[R] <= model.model.planet.radius {
                break;
            }
            let c = model.trigger_fn(&next);
            if armed && c <= 0.0 {
                last = Some(x);
                break;
            }
            armed |= c > 0.0;
            let (_, phi) = ad_jacobian(|y| model.step(&y, h), &x);
            stms.push(phi);
            x = next;
            states.push(x);
        }
        let Some(xn) = last else {
            return Err(GuidanceError::ReferenceNoTrigger {
                bank_deg: s.bank.to_degrees(),
                max_time_s: s.max_time_s,
                altitude_m: x[R] - model.model.planet.radius,
                speed_mps: x[V],
            });
        };
        // Final partial step x_N → x_f of length h*(x_N), differentiated with its length.
        let hs = model.crossing_step(&xn, h);
        let xf = model.step(&xn, hs);
        let (_, m) = ad_jacobian(|y| model.step(&y, hs), &xn);
        let (_, grad_c) = ad_jacobian(|y| SVector::<_, 1>::from([model.trigger_fn(&y)]), &xf);
        let ff = model.rhs(&xf);
        let cdot = (grad_c * ff)[0];
        let mut lam_f: SVector<f64, 5> = SVector::zeros();
        lam_f[THETA] = 1.0;
        lam_f -= grad_c.transpose() * (ff[THETA] / cdot);
        // λ at x_N, then backwards through the full steps.
        let mut lam = vec![SVector::<f64, 5>::zeros(); states.len()];
        lam[states.len() - 1] = m.transpose() * lam_f;
        for k in (0..stms.len()).rev() {
            lam[k] = stms[k].transpose() * lam[k + 1];
        }
        let radius = model.model.planet.radius;
        let theta_f = xf[THETA];
        // Tabulate from peak speed on (the speed rises at first under gravity).
        let peak = (0..states.len())
            .max_by(|&a, &b| states[a][V].total_cmp(&states[b][V]))
            .unwrap_or(0);
        let mut points = Vec::new();
        for k in peak..states.len() {
            let xk = states[k];
            let (d, dd_dr) = {
                let (val, jac) = ad_jacobian(
                    |y: SVector<_, 5>| SVector::<_, 1>::from([model.drag(y[R], y[V])]),
                    &xk,
                );
                (val[0], jac[(0, R)])
            };
            let l = lam[k];
            points.push(ReferencePoint {
                t: k as f64 * h,
                x: xk.into(),
                drag: d,
                rdot: xk[V] * xk[GAMMA].sin(),
                range_to_go: radius * (theta_f - xk[THETA]),
                lambda: l.into(),
                f1: radius * l[R] / dd_dr,
                f2: radius * l[GAMMA] / (xk[V] * xk[GAMMA].cos()),
                f3: radius * l[U],
            });
        }
        if points.len() < 3 {
            return Err(GuidanceError::ReferenceTooShort {
                points: points.len(),
            });
        }
        Ok(ReferenceTrajectory {
            bank: s.bank,
            vertical_ld: u,
            theta_final: theta_f,
            final_state: xf.into(),
            points,
        })
    }

    /// The reference at speed `v`, linearly interpolated (clamped to the table's ends).
    pub fn at_speed(&self, v: f64) -> ReferencePoint {
        let p = &self.points;
        // Speeds decrease along the table: first index with speed ≤ v.
        let i = p.partition_point(|q| q.x[V] > v);
        if i == 0 {
            return p[0];
        }
        if i >= p.len() {
            return p[p.len() - 1];
        }
        let (a, b) = (&p[i - 1], &p[i]);
        let w = (a.x[V] - v) / (a.x[V] - b.x[V]);
        let lerp = |x: f64, y: f64| x + w * (y - x);
        ReferencePoint {
            t: lerp(a.t, b.t),
            x: std::array::from_fn(|j| lerp(a.x[j], b.x[j])),
            drag: lerp(a.drag, b.drag),
            rdot: lerp(a.rdot, b.rdot),
            range_to_go: lerp(a.range_to_go, b.range_to_go),
            lambda: std::array::from_fn(|j| lerp(a.lambda[j], b.lambda[j])),
            f1: lerp(a.f1, b.f1),
            f2: lerp(a.f2, b.f2),
            f3: lerp(a.f3, b.f3),
        }
    }

    /// The speed at the reference's peak drag \[m/s\].
    pub fn peak_drag_speed(&self) -> f64 {
        self.points
            .iter()
            .max_by(|a, b| a.drag.total_cmp(&b.drag))
            .map_or(0.0, |p| p.x[V])
    }

    /// The reference's downrange flown to the trigger \[m\] on the sphere of radius `radius`.
    pub fn total_range(&self, radius: f64) -> f64 {
        radius * self.theta_final
    }
}
