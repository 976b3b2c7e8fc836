//! Online maximum-likelihood adaptation of the density network: seed 001 §IV.B.2, eq. 52–60,
//! Algorithm 2.
//!
//! The loss is the measurement log-likelihood at the prior mean (eq. 52–53),
//! `𝓛(ξ) = Σⱼ [yⱼ − h(x̂ⱼ⁻, NN(r̂ⱼ⁻, ξ))]ᵀ Rⱼ⁻¹ [·]` over a window of epochs (one — the current
//! one — in seed 001; more is the §VI extension). Its gradient is
//! `∇ξ𝓛 = Σⱼ (∂𝓛/∂ρⱼ) ∂NN(r̂ⱼ⁻)/∂ξ` with `∂𝓛/∂ρⱼ = −2 νⱼᵀ Rⱼ⁻¹ ∂h/∂ρ`, where ∂h/∂ρ comes
//! from forward-mode AD through the scenario's measurement model (a dual-number density) and
//! ∂NN/∂ξ from the network's backpropagation.
//!
//! Algorithm 2: while 𝓛 > 𝒯, take an Adam candidate (eq. 55–57: ∇̄* = β₁∇̄ + (1 − β₁)∇,
//! (∇̄*)² = β₂(∇̄)² + (1 − β₂)∇², ξ* = ξ − α_𝓛 ∇̄*/(√(∇̄*)² + ε), no bias correction); accept it
//! with its moments if it lowers the loss (eq. 58–60), otherwise count patience and stop at
//! p_max. The first gradient initialises ∇̄ = 0 and (∇̄)² = ∇² (seed 001 §IV.B.2). With
//! p_max = 1 (Table 4) the first rejected candidate ends the loop; for p_max > 1 a rejected
//! candidate keeps ξ but passes its moments on, so that the retry differs (an unchanged state
//! would reproduce the rejected candidate exactly).

use super::adam::Adam;
use super::network::DensityNetworkSet;
use super::nn::Activations;
use crate::atmosphere::Atmosphere;
use crate::dynamics::EntryModel;
use crate::math::V3;
use crate::sensors::channels::{Channel, Kinematics, MeasurementModel};
use nalgebra::SVector;
use num_dual::Dual64;

/// Settings of Algorithm 2 (seed 001 Table 4).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct MloSettings {
    /// β₁ (0.1).
    pub beta1: f64,
    /// β₂ (0.9).
    pub beta2: f64,
    /// ε of eq. 57.
    pub epsilon: f64,
    /// α_𝓛 = step / k (0.01).
    pub step: f64,
    /// p_max (1).
    pub patience: usize,
    /// 𝒯: optimise only while the loss exceeds it.
    pub threshold: f64,
    /// Cap on iterations per call.
    pub max_iterations: usize,
}

/// One measurement epoch in the loss: the prior kinematics it is evaluated at, the measured
/// values, the inverse noise variances and the channels.
#[derive(Debug, Clone)]
pub struct LossTerm<const N: usize = 8> {
    /// Prior navigation state (kinematic + augmented states).
    pub x: SVector<f64, N>,
    /// Kinematics of `x` (density unused).
    pub kin: Kinematics<f64>,
    /// Altitude of `x` \[m\].
    pub altitude: f64,
    /// Measured values.
    pub z: Vec<f64>,
    /// 1/σ² of each value.
    pub r_inv: Vec<f64>,
    /// Channels of `z`.
    pub channels: Vec<Channel>,
    /// Beacon states at the epoch.
    pub beacons: Vec<(V3<f64>, V3<f64>)>,
}

/// The measurement model and vehicle context the loss is evaluated in.
pub struct LossContext<'a, A> {
    /// Scenario's measurement model.
    pub measurement: &'a MeasurementModel,
    /// Onboard dynamics: only its vehicle/augmented-state layout is used (the density comes from
    /// the network set, never from this model's atmosphere).
    pub model: &'a EntryModel<A>,
    /// Bank angle \[rad\].
    pub bank: f64,
}

impl<A: Atmosphere> LossContext<'_, A> {
    /// Loss of `terms` under `set` (eq. 52), adding its gradient for band `band` into `grad` if
    /// given (terms served by other bands contribute to the loss only).
    pub fn loss<const N: usize>(
        &self,
        set: &DensityNetworkSet,
        terms: &[LossTerm<N>],
        band: usize,
        mut grad: Option<&mut [f64]>,
        act: &mut Activations,
    ) -> f64 {
        let mut total = 0.0;
        for term in terms {
            let b = set.band(term.altitude);
            let net = &set.nets[b];
            let r = term.altitude + set.planet_radius_m;
            let i = net.input(r);
            // The local correction (identity without `slope_window`) multiplies ρ, so
            // ∂ρ/∂o keeps its form with the corrected ρ.
            let f = set.correction.factor(term.altitude);
            match grad.as_deref_mut() {
                Some(g) if b == band => {
                    let o = net.forward(i, act);
                    let varrho = net.norm.out_std * o + net.norm.out_mean;
                    let rho = net.norm.untransform(varrho) * f;
                    let (l, dl_drho) = self.term_loss(term, rho);
                    total += l;
                    let drho_do = -2.0 * std::f64::consts::LN_10 * rho * varrho * net.norm.out_std;
                    net.backward_output(i, dl_drho * drho_do, g, act);
                }
                _ => total += self.term_loss(term, net.density(r) * f).0,
            }
        }
        total
    }

    /// One term's loss νᵀR⁻¹ν and its derivative with respect to the density.
    pub fn term_loss<const N: usize>(&self, term: &LossTerm<N>, rho: f64) -> (f64, f64) {
        let (mut l, mut dl) = (0.0, 0.0);
        self.for_each_residual(term, rho, |nu, dh_drho, ri| {
            l += nu * nu * ri;
            dl += -2.0 * nu * ri * dh_drho;
        });
        (l, dl)
    }

    /// The log-density the term's measurements imply at its prior state: `u = ln ρ` minimising
    /// the term's loss (eq. 52 with the density free), by Gauss–Newton from `rho0`
    /// (`u ← u + Σ Jᵢ rᵢ νᵢ / Σ Jᵢ² rᵢ`, `Jᵢ = ∂hᵢ/∂u = ρ ∂hᵢ/∂ρ`), and its information
    /// `Σ Jᵢ² rᵢ` at the solution (1/σ_u² from the measurement noise alone). `None` when no
    /// measurement depends on the density or the iteration does not settle.
    pub fn measured_log_density<const N: usize>(
        &self,
        term: &LossTerm<N>,
        rho0: f64,
    ) -> Option<(f64, f64)> {
        let mut u = rho0.ln();
        for _ in 0..20 {
            let rho = u.exp();
            let (mut g, mut info) = (0.0, 0.0);
            self.for_each_residual(term, rho, |nu, dh_drho, ri| {
                let j = rho * dh_drho;
                g += j * ri * nu;
                info += j * j * ri;
            });
            if !(info > 0.0 && g.is_finite()) {
                return None;
            }
            let du = (g / info).clamp(-2.0, 2.0);
            u += du;
            if du.abs() < 1e-9 {
                return Some((u, info));
            }
        }
        None
    }

    /// Calls `each(ν, ∂h/∂ρ, 1/σ²)` for every measured value of `term` with density `rho`.
    fn for_each_residual<const N: usize>(
        &self,
        term: &LossTerm<N>,
        rho: f64,
        mut each: impl FnMut(f64, f64, f64),
    ) {
        let xd: SVector<Dual64, N> = term.x.map(Dual64::from);
        let lift = |v: &V3<f64>| v.map(Dual64::from);
        let kin = Kinematics {
            pos: lift(&term.kin.pos),
            vel: lift(&term.kin.vel),
            airspeed: Dual64::from(term.kin.airspeed),
            density: Dual64::new(rho, 1.0),
        };
        let mut triad = None;
        for ((&ch, &z), &ri) in term.channels.iter().zip(&term.z).zip(&term.r_inv) {
            let h = self.measurement.evaluate_sharing_triad(
                self.model,
                &xd,
                &kin,
                self.bank,
                &term.beacons,
                ch,
                &mut triad,
            );
            each(z - h.re, h.eps, ri);
        }
    }
}

/// Adam state of the online adaptation for one network (moments created at the first gradient).
#[derive(Debug, Clone, PartialEq, Default)]
pub struct OnlineAdam {
    /// Moments, `None` before the first gradient.
    pub adam: Option<Adam>,
}

/// What one call of Algorithm 2 did.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct MloOutcome {
    /// Loss before.
    pub initial_loss: f64,
    /// Loss after.
    pub final_loss: f64,
    /// Candidates evaluated.
    pub iterations: usize,
    /// Candidates accepted.
    pub accepted: usize,
}

/// Algorithm 2 on the network of `band` with step size `lr` (= α_𝓛 at this epoch).
#[allow(clippy::too_many_arguments)]
pub fn maximise_likelihood<A: Atmosphere, const N: usize>(
    ctx: &LossContext<'_, A>,
    set: &mut DensityNetworkSet,
    band: usize,
    state: &mut OnlineAdam,
    terms: &[LossTerm<N>],
    lr: f64,
    s: &MloSettings,
    act: &mut Activations,
) -> MloOutcome {
    let np = set.nets[band].n_params();
    let mut grad = vec![0.0; np];
    let mut loss = ctx.loss(set, terms, band, Some(&mut grad), act);
    let mut out = MloOutcome {
        initial_loss: loss,
        final_loss: loss,
        ..Default::default()
    };
    if loss <= s.threshold || !loss.is_finite() {
        return out;
    }
    let adam = state.adam.get_or_insert_with(|| {
        let mut a = Adam::new(np, s.beta1, s.beta2, s.epsilon, false);
        a.v = grad.iter().map(|g| g * g).collect();
        a
    });
    let mut xi_new = vec![0.0; np];
    let mut m_new = vec![0.0; np];
    let mut v_new = vec![0.0; np];
    let mut grad_new = vec![0.0; np];
    let mut patience = 0;
    while loss > s.threshold && out.iterations < s.max_iterations {
        out.iterations += 1;
        adam.candidate(
            set.nets[band].params(),
            &grad,
            lr,
            &mut xi_new,
            &mut m_new,
            &mut v_new,
        );
        set.nets[band].params_mut().swap_with_slice(&mut xi_new);
        grad_new.iter_mut().for_each(|g| *g = 0.0);
        let l_new = ctx.loss(set, terms, band, Some(&mut grad_new), act);
        if l_new < loss {
            out.accepted += 1;
            std::mem::swap(&mut adam.m, &mut m_new);
            std::mem::swap(&mut adam.v, &mut v_new);
            std::mem::swap(&mut grad, &mut grad_new);
            loss = l_new;
        } else {
            set.nets[band].params_mut().swap_with_slice(&mut xi_new);
            patience += 1;
            if patience >= s.patience {
                break;
            }
            // p_max > 1 (not used by seed 001): keep ξ but take the candidate's moments, so
            // that the retry is a different step (retrying with unchanged moments would
            // reproduce the rejected candidate exactly).
            std::mem::swap(&mut adam.m, &mut m_new);
            std::mem::swap(&mut adam.v, &mut v_new);
        }
    }
    out.final_loss = loss;
    out
}
