//! USKF-NN: the unscented Schmidt–Kalman filter with an online-adapted density network (seed 001
//! §IV.B, eq. 39–68, Algorithms 2–3).
//!
//! Internally the state is augmented with the consider parameter c (eq. 39–40):
//! `x̂ₐ = [r, lon, lat, v, γ, ψ, B, L/D, c]`, ĉ₀ = 1, C₀ = 0, P_c,0 = 1e-10. One step (Algorithm 3):
//!
//! 1. **Time propagation** (eq. 41–51): sigma points of (x̂ₐ⁺, Pₐ⁺) are propagated by RK4 with the
//!    density `𝒫⁽ⁱ⁾ = c⁽ⁱ⁾·NN(r⁽ⁱ⁾, ξ_{k−1})` (eq. 45); c is an exponentially correlated random
//!    variable centred at one, `c ← 1 + e^{−Δt/τ}(c − 1)` with
//!    `Q_c = (1 − e^{−2Δt/τ}) P_ss` (eq. 51; τ = 5 s, P_ss = 1e-3).
//! 2. **Maximum-likelihood optimisation** (Algorithm 2, [`maximise_likelihood`]) of the network
//!    at the prior mean, loss eq. 52–53, Adam with β₁ = 0.1, β₂ = 0.9, p_max and step
//!    α_𝓛 = `adam_step`/k at measurement epoch k, only while the loss exceeds 𝒯. Table 4 has
//!    p_max = 1 and α_𝓛 = 0.01/k (scenario `msl-airdata-paper`); `msl-airdata` uses p_max = 5 and
//!    0.001/k, whose smaller first steps avoid the wrong-network lock-on (docs/density.md).
//! 3. **Measurement update** (eq. 61–68) with the adapted network ξ_k and the Schmidt update:
//!    the consider parameter and its variance are not updated, its cross-covariance is
//!    ([`Ukf`] with `n_consider = 1`).
//!
//! The filter is generic over the navigation dimension `N` (8 for seed 001's layout) with
//! `L = N + 1` internal states.
//!
//! Options (seed 001 §VI, future work): `filter.density.window > 1` puts the last `window`
//! measurement epochs (each at its own prior mean) in the loss; a network file with several
//! altitude bands uses one network per band and adapts the one serving the prior altitude.
//!
//! Option (ours): `filter.density.slope_window` (epochs) multiplies the network density by a local
//! level-and-slope correction `exp(a + b (h − h_k))` refitted before step 2 at every epoch to the
//! log-densities the last `slope_window` epochs' measurements imply at their prior states
//! ([`crate::estimation::adaptive::local_fit`]); Algorithm 2 then adapts the network to what the
//! correction leaves. `msl-airdata` uses 2 epochs.
//!
//! Option (ours, with the correction): `filter.density.consider_match_epochs = n` sets the
//! consider parameter's variance at each update to the larger of P_ss and the variance of the
//! correction's one-step prediction error, `e_k = u_k − ln ρ̂(h_k)` (the log-density epoch k's
//! measurements imply against the density the last correction predicts there), less the
//! measurement noise's share, averaged with weight 1/n: covariance matching (Myers & Tapley,
//! "Adaptive sequential estimation with unknown noise statistics", IEEE TAC 21(4), 1976) applied
//! to c. The row and column of c in P are rescaled (a congruence, so P stays positive
//! definite). Why: high in the entry a rough truth atmosphere changes the density by ~10 % between
//! epochs that the correction cannot predict, and c's P_ss = 1e-4 let the update read the
//! radius from the density's slope: σ_r fell from 10.6 to 6.9 m while the error stayed at 11 m
//! (msl-airdata, docs/process-noise.md).

use super::nav_filter::{FilterCore, NavFilter};
use super::start::FilterStart;
use super::step_info::StepInfo;
use super::ukf_ac::augment_start;
use super::ukf_common::{UkfCore, epoch_measurements};
use crate::dynamics::EntryModel;
use crate::estimation::adaptive::local_fit::LocalSlopeFit;
use crate::estimation::adaptive::mlo::{
    LossContext, LossTerm, MloOutcome, MloSettings, OnlineAdam, maximise_likelihood,
};
use crate::estimation::adaptive::network::{DensityNetworkSet, NnAtmosphere};
use crate::estimation::adaptive::nn::Activations;
use crate::estimation::adaptive::onboard_networks::load_network_set;
use crate::estimation::error::EstimationError;
use crate::estimation::onboard::Onboard;
use crate::estimation::ukf::Ukf;
use crate::math::V3;
use crate::sensors::MeasurementEpoch;
use crate::sensors::channels::kinematics;
use nalgebra::{SMatrix, SVector};
use std::collections::VecDeque;
use std::sync::Arc;

/// Running totals of the online adaptation (diagnostics).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct AdaptationStats {
    /// Measurement epochs processed.
    pub epochs: usize,
    /// Epochs whose loss exceeded the threshold (the optimiser ran).
    pub optimised: usize,
    /// Adam candidates evaluated.
    pub iterations: usize,
    /// Adam candidates accepted.
    pub accepted: usize,
    /// The last epoch's outcome.
    pub last: MloOutcome,
}

/// Unscented Schmidt–Kalman filter with the adapted density network (`uskf-nn`), for spherical
/// scenarios with seed 001's augmented layout: `N` navigation states plus the consider parameter
/// c, `L = N + 1` states inside.
#[derive(Debug, Clone)]
pub struct UskfNnNav<const N: usize, const L: usize> {
    core: UkfCore<NnAtmosphere, L>,
    /// Process noise of the navigation states per filter step.
    q: SMatrix<f64, N, N>,
    tau: f64,
    pss: f64,
    settings: MloSettings,
    window: usize,
    terms: VecDeque<LossTerm<N>>,
    adam: Vec<OnlineAdam>,
    /// The local level-and-slope correction's window (`slope_window` given).
    slope: Option<LocalSlopeFit>,
    /// Covariance matching of c: the average's weight 1/n (`consider_match_epochs` given) and
    /// the running mean of the correction's squared one-step prediction error.
    match_weight: Option<f64>,
    prediction_var: Option<f64>,
    act: Activations,
    stats: AdaptationStats,
}

impl<const N: usize, const L: usize> UskfNnNav<N, L> {
    /// A USKF-NN on the `onboard` models from `start`, with the network of
    /// `filter.density.network`.
    pub fn new(onboard: &Arc<Onboard>, start: &FilterStart<N>) -> Result<Self, EstimationError> {
        let set =
            load_network_set(onboard).map_err(|e| EstimationError::InvalidInput(e.to_string()))?;
        Self::with_networks(onboard, start, set)
    }

    /// As [`UskfNnNav::new`] with the networks `set` instead of `filter.density.network` (e.g. a
    /// network just trained).
    pub fn with_networks(
        onboard: &Arc<Onboard>,
        start: &FilterStart<N>,
        set: DensityNetworkSet,
    ) -> Result<Self, EstimationError> {
        let cfg = onboard.tuning.density_settings();
        let nb = set.nets.len();
        let fm = &onboard.model;
        let model = EntryModel {
            kind: fm.kind,
            planet: fm.planet,
            atmosphere: NnAtmosphere { set },
            vehicle: fm.vehicle,
            augmented: fm.augmented.clone(),
            rho0_model: 1.0,
            density_factor: 1.0,
            bias_tau_s: fm.bias_tau_s,
        };
        let aug = augment_start::<N, L>(start, 1.0, cfg.consider_p0, 0.0)?;
        let ukf = Ukf::new(aug.x0, aug.p0, onboard.tuning.ukf, 1)?;
        Ok(UskfNnNav {
            // eq. 45, 62: the consider parameter c (state N) scales the network's density.
            core: UkfCore::new(onboard, model, ukf, Some(N)),
            q: start.q,
            tau: cfg.consider_tau_s,
            pss: cfg.consider_pss,
            settings: MloSettings {
                beta1: cfg.adam_beta1,
                beta2: cfg.adam_beta2,
                epsilon: cfg.adam_epsilon,
                step: cfg.adam_step,
                patience: cfg.patience,
                threshold: cfg.loss_threshold,
                max_iterations: cfg.max_iterations,
            },
            window: cfg.window.max(1),
            terms: VecDeque::with_capacity(cfg.window.max(1) + 1),
            adam: vec![OnlineAdam::default(); nb],
            slope: cfg.slope_window.map(|w| {
                LocalSlopeFit::new(w, cfg.slope_sigma_per_km, cfg.slope_log_density_sigma)
            }),
            // Used only with the correction (validation refuses it without).
            match_weight: cfg.consider_match_epochs.map(|n| 1.0 / n.max(1) as f64),
            prediction_var: None,
            act: Activations::default(),
            stats: AdaptationStats::default(),
        })
    }

    /// The filter's density profile ĉ·NN(R + h, ξ_k) at altitude `altitude_m` [kg/m³].
    pub fn density_profile(&self, altitude_m: f64) -> f64 {
        self.core.ukf.x[N]
            * self
                .core
                .model
                .atmosphere
                .set
                .density_at_altitude(altitude_m)
    }

    /// The adapted onboard atmosphere (network set ξ_k).
    pub fn atmosphere(&self) -> &NnAtmosphere {
        &self.core.model.atmosphere
    }

    /// Adaptation diagnostics.
    pub fn adaptation_stats(&self) -> AdaptationStats {
        self.stats
    }

    /// Augmented estimate [x̂; ĉ] and covariance.
    pub fn augmented(&self) -> (SVector<f64, L>, SMatrix<f64, L, L>) {
        (self.core.ukf.x, self.core.ukf.p)
    }
}

impl<const N: usize, const L: usize> NavFilter<N> for UskfNnNav<N, L> {
    fn predict(&mut self, t_to: f64) -> Result<(), EstimationError> {
        let Some((n, h, step)) = self.core.substeps_to(t_to)? else {
            return Ok(());
        };
        // eq. 51: ECRV transition and its process noise.
        let phi = (-h / self.tau).exp();
        let mut q = SMatrix::<f64, L, L>::zeros();
        q.fixed_view_mut::<N, N>(0, 0)
            .copy_from(&(self.q * (h / step)));
        q[(N, N)] = (1.0 - phi * phi) * self.pss;
        // eq. 44–45: sigma point i flies the density c⁽ⁱ⁾·NN(r⁽ⁱ⁾, ξ_{k−1}); c decays to 1.
        self.core
            .propagate(t_to, n, h, &q, |x, y| y[N] = 1.0 + phi * (x[N] - 1.0))
            .map(|_| ())
    }

    fn update(
        &mut self,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
    ) -> Result<StepInfo, EstimationError> {
        let Some((slots, z, r)) = epoch_measurements(&self.core.onboard, epoch) else {
            return Ok(StepInfo::default());
        };
        let sc = &*self.core.onboard;
        let (t, bank) = (epoch.t, self.core.bank);

        // Algorithm 2 at the prior mean (eq. 52–53).
        self.stats.epochs += 1;
        let k = self.stats.epochs;
        let xn: SVector<f64, N> = self.core.ukf.x.fixed_rows::<N>(0).into_owned();
        let altitude = self.core.model.altitude(&xn);
        let term = LossTerm {
            x: xn,
            kin: kinematics(&sc.model, &xn, t),
            altitude,
            z: z.iter().copied().collect(),
            r_inv: r.diagonal().iter().map(|v| 1.0 / v).collect(),
            channels: slots.iter().map(|&c| sc.channels[c].channel).collect(),
            beacons: beacons.to_vec(),
        };
        self.terms.push_back(term);
        while self.terms.len() > self.window {
            self.terms.pop_front();
        }
        let band = self.core.model.atmosphere.set.band(altitude);
        let ctx = LossContext {
            measurement: &sc.measurement,
            model: &sc.model,
            bank,
        };
        // The local level-and-slope correction (option), from this epoch's implied density.
        if let Some(fit) = &mut self.slope {
            let set = &mut self.core.model.atmosphere.set;
            let rho0 = set.density_at_altitude(altitude);
            if let Some((u, info)) =
                ctx.measured_log_density(self.terms.back().expect("pushed above"), rho0)
            {
                // rho0 is what the last correction predicts here: its error, less the noise's.
                if let (Some(w), false) = (self.match_weight, fit.is_empty()) {
                    let v = (u - rho0.ln()).powi(2) - 1.0 / info;
                    self.prediction_var =
                        Some(self.prediction_var.map_or(v, |p| (1.0 - w) * p + w * v));
                }
                fit.push(altitude, u);
            }
            set.correction = fit.fit(|h| set.network_density(h).ln(), altitude);
        }
        if let Some(var) = self.prediction_var {
            let target = var.max(self.pss).min(MAX_MATCHED_CONSIDER_VAR);
            rescale_variance(&mut self.core.ukf.p, N, target);
        }
        let outcome = maximise_likelihood(
            &ctx,
            &mut self.core.model.atmosphere.set,
            band,
            &mut self.adam[band],
            self.terms.make_contiguous(),
            self.settings.step / k as f64,
            &self.settings,
            &mut self.act,
        );
        if outcome.iterations > 0 {
            self.stats.optimised += 1;
        }
        self.stats.iterations += outcome.iterations;
        self.stats.accepted += outcome.accepted;
        self.stats.last = outcome;

        // eq. 61–68 with ξ_k.
        self.core.update_measured(&slots, &z, &r, t, beacons)
    }

    fn core(&self) -> &dyn FilterCore<N> {
        &self.core
    }

    fn core_mut(&mut self) -> &mut dyn FilterCore<N> {
        &mut self.core
    }

    /// ĉ·NN(R + h, ξ_k); at the posterior estimate's altitude it is the density estimate.
    fn density_profile(&self, altitude_m: f64) -> Option<f64> {
        Some(Self::density_profile(self, altitude_m))
    }
}

/// The largest variance covariance matching gives c (σ 32 %): c's sigma points, 1 ± √(L + κ)·σ
/// with L + κ = 3 (α = 1), stay above 0.45, so no sigma point flies a negative density. The
/// largest matched variance measured with the correction is 9·10⁻³ (msl-airdata at 125 km);
/// without it the first epochs' level error reached 100 % and 17 of 60 msl-guided runs failed
/// (why the option needs `slope_window`).
const MAX_MATCHED_CONSIDER_VAR: f64 = 0.1;

/// Scales row and column `i` of `p` so that `p[(i, i)] = target` (a congruence D·P·D with one
/// diagonal entry of D not 1: P stays positive definite). Nothing when either variance is not
/// positive and finite.
fn rescale_variance<const L: usize>(p: &mut SMatrix<f64, L, L>, i: usize, target: f64) {
    let now = p[(i, i)];
    if !(now > 0.0 && now.is_finite() && target > 0.0 && target.is_finite()) {
        return;
    }
    let f = (target / now).sqrt();
    for j in 0..L {
        p[(i, j)] *= f;
        p[(j, i)] *= f;
    }
}

#[cfg(test)]
mod tests {
    use super::rescale_variance;
    use nalgebra::Matrix3;

    #[test]
    fn rescaling_a_variance_keeps_the_correlations_and_positive_definiteness() {
        let p0 = Matrix3::new(4.0, 1.2, -0.3, 1.2, 9.0, 0.5, -0.3, 0.5, 0.25);
        let corr =
            |p: &Matrix3<f64>, i: usize, j: usize| p[(i, j)] / (p[(i, i)] * p[(j, j)]).sqrt();
        for target in [1e-8, 3e-3, 2.0] {
            let mut p = p0;
            rescale_variance(&mut p, 2, target);
            assert!((p[(2, 2)] / target - 1.0).abs() < 1e-12);
            assert_eq!((p[(0, 0)], p[(1, 1)], p[(0, 1)]), (4.0, 9.0, 1.2));
            for (i, j) in [(0, 2), (1, 2)] {
                assert!((corr(&p, i, j) - corr(&p0, i, j)).abs() < 1e-12);
                assert_eq!(p[(i, j)], p[(j, i)]);
            }
            assert!(p.cholesky().is_some());
        }
        assert!(p0.cholesky().is_some());
        // A non-positive or non-finite target leaves P as it was.
        for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            let mut p = p0;
            rescale_variance(&mut p, 2, bad);
            assert_eq!(p, p0);
        }
    }
}
