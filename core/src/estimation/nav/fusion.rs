//! Distributed fusion: one local EKF per beacon (IMU + that beacon), fused by covariance
//! intersection, with or without information feedback (seed 000 §2.3.3, §3.3–3.4).

use super::ekf_nav::{EkfNav, RELINEARIZATION_TOLERANCE};
use super::ensemble::EkfEnsemble;
use super::fusion_pass::{FusionPass, fusion_pass};
use super::fusion_setup::{local_masks, local_start_scale, weighting};
use super::nav_filter::{FilterCore, NavFilter};
use super::prior_information::PriorInformation;
use super::start::FilterStart;
use super::step_info::StepInfo;
use crate::estimation::ci::{CiWeighting, covariance_intersection_from, feedback};
use crate::estimation::error::EstimationError;
use crate::estimation::linearization::linearization_error_values;
use crate::estimation::onboard::{FusionCovariance, Onboard};
use crate::math::V3;
use crate::math::all_finite;
use crate::sensors::MeasurementEpoch;
use nalgebra::{SMatrix, SVector};
use std::sync::Arc;

/// What the local filters are called in errors.
const LOCAL: &str = "local filter";

/// CI fusion of local filters.
///
/// * `ci` (no feedback): the local filters run independently from P0; each step their posteriors
///   are fused with determinant-optimal weights (the paper's "slowest" variant).
/// * `dcifaif`: fast ∞-norm weights (eq. 21) and information feedback. With
///   `fusion_covariance = "exact"` (the default) the fused covariance is the exact covariance of
///   the CI-weighted estimate and every local filter is reset to it (`nav/fusion_exact.rs`);
///   with `"paper"` the fused covariance is the CI bound and every local filter is reset to
///   (x̂_CI, P_CI/ω_i) (eq. 22), starting from (x̂0, n·P0), the equal-weight feedback of (x̂0, P0).
///
/// A local filter that fails numerically is dropped from the fusion (its subsystem is weakly
/// observable, seed 000 §2.4); the filter fails only when every local filter has.
#[derive(Debug, Clone)]
pub struct FusionNav<const N: usize> {
    /// The local filters and the fused estimate.
    ens: EkfEnsemble<N>,
    method: CiWeighting,
    feedback: bool,
    /// Feedback with the exact fused covariance (`dcifaif` with `fusion_covariance = "exact"`).
    exact: bool,
    /// Number of consider parameters (the last states).
    n_consider: usize,
    /// Beacons the innovation gate has excluded: their local filters leave the fusion.
    excluded: Vec<usize>,
    /// The last fusion's weights per local filter (0 for those not fused): the next epoch's
    /// optimal-weight search starts from them (`covariance_intersection_from`).
    last_weights: Vec<f64>,
}

impl<const N: usize> FusionNav<N> {
    /// Local filters over the non-radio channels plus the radio channels of each beacon.
    pub fn new(
        onboard: &Arc<Onboard>,
        start: &FilterStart<N>,
        with_feedback: bool,
    ) -> Result<Self, EstimationError> {
        let masks = local_masks(onboard);
        let exact = with_feedback && onboard.tuning.fusion_covariance == FusionCovariance::Exact;
        let mut local_start = start.clone();
        local_start.p0 = start.p0 * local_start_scale(masks.len(), with_feedback, exact);
        let mut locals = Vec::new();
        for mask in masks {
            locals.push(EkfNav::new(onboard, &local_start, Some(mask), 1.0)?);
        }
        if locals.len() < 2 {
            return Err(EstimationError::InvalidInput(
                "CI fusion needs at least two beacons with radio channels".into(),
            ));
        }
        let method = weighting(with_feedback);
        Ok(FusionNav {
            ens: EkfEnsemble::new(onboard, locals, (start.x0, start.p0)),
            method,
            feedback: with_feedback,
            exact,
            n_consider: onboard.tuning.n_consider,
            excluded: Vec::new(),
            last_weights: Vec::new(),
        })
    }

    /// Whether local filter `f` listens to an excluded beacon (and so leaves the fusion).
    fn leaves_fusion(&self, f: &EkfNav<N>) -> bool {
        let beacon = |c: &usize| self.ens.onboard.channels.get(*c)?.channel.beacon();
        f.channel_mask()
            .iter()
            .any(|c| beacon(c).is_some_and(|b| self.excluded.contains(&b)))
    }

    /// The live members that take part in the fusion: all but those of excluded beacons (all,
    /// if that would leave none).
    fn fusing(&self) -> Vec<usize> {
        let live: Vec<usize> = (0..self.ens.members.len())
            .filter(|&i| self.ens.members[i].is_some())
            .collect();
        let kept: Vec<usize> = live
            .iter()
            .copied()
            .filter(|&i| {
                self.ens.members[i]
                    .as_ref()
                    .is_some_and(|f| !self.leaves_fusion(f))
            })
            .collect();
        if kept.is_empty() { live } else { kept }
    }
}

impl<const N: usize> FusionNav<N> {
    /// With feedback every local filter holds x̂_CI: each sub-step's mean and Φ, computed once,
    /// serve them all.
    fn predict_shared(&mut self, t_to: f64) -> Result<(), EstimationError> {
        let Some(first) = self.ens.first() else {
            return Err(EkfEnsemble::<N>::all_failed(LOCAL));
        };
        let (n, h, q) = first.substeps_to(t_to)?;
        for _ in 0..n {
            let Some((x_next, phi, q)) = self.ens.first().map(|f| {
                let (x_next, phi) = f.substep(h);
                (x_next, phi, f.substep_noise(h, &phi, &q))
            }) else {
                break;
            };
            // Locals whose covariance equals an earlier local's (bit for bit: all of them with
            // the exact feedback, which resets every local to the fused (x̂, P)) take its
            // predicted covariance instead of computing Φ P Φᵀ + Q again: the same operations on
            // the same numbers, so the same result.
            let mut done: Vec<(SMatrix<f64, N, N>, Option<SMatrix<f64, N, N>>)> = Vec::new();
            for slot in self.ens.members.iter_mut() {
                let Some(f) = slot else { continue };
                let prior = f.estimate().1;
                let post = match done.iter().find(|(p, _)| p.as_slice() == prior.as_slice()) {
                    Some((_, post)) => *post,
                    None => {
                        let post = f
                            .apply_substep(x_next, &phi, &q)
                            .ok()
                            .map(|_| f.estimate().1);
                        done.push((prior, post));
                        post
                    }
                };
                match post {
                    Some(p) => f.set_estimate(x_next, p),
                    None => *slot = None,
                }
            }
        }
        for f in self.ens.members.iter_mut().flatten() {
            f.finish_prediction(t_to);
        }
        self.ens.t = t_to;
        Ok(())
    }

    /// The exact-covariance update: every live local updates the common prior with its channels,
    /// the updates are fused with fast CI weights and the exact covariance, and every local is
    /// reset to the result.
    fn update_exact(
        &mut self,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
    ) -> Result<StepInfo, EstimationError> {
        let Some(first) = self.ens.first() else {
            return Err(EkfEnsemble::<N>::all_failed(LOCAL));
        };
        let (x, p) = first.estimate();
        let iterations = first.update_iterations();
        let mut items = first.all_measurement_items(epoch, beacons);
        let all_slots: Vec<usize> = items.iter().map(|(c, _)| *c).collect();
        let fusing = self.fusing();
        let masks: Vec<(usize, &[usize])> = self
            .ens
            .members
            .iter()
            .enumerate()
            .filter(|(i, _)| fusing.contains(i))
            .filter_map(|(i, f)| f.as_ref().map(|f| (i, f.channel_mask())))
            .collect();
        // Iterated EKF (EkfNav::update_iterated) for the fusion: every local updates the common
        // prior with its channels linearised at the *fused* iterate, which the fusion centre feeds
        // back within the epoch; a local's own iterate would stay as far off as its one range
        // leaves it.
        // The prior's information, factored once for every pass of the epoch (none with consider
        // states, whose posteriors are not in information form).
        let info = match self.n_consider {
            0 => Some(PriorInformation::new(&p)?),
            _ => None,
        };
        let mut lin = x;
        let mut pass = fusion_pass(
            &x,
            &p,
            info.as_ref(),
            &lin,
            &items,
            &masks,
            self.ens.members.len(),
            self.n_consider,
        )?;
        for _ in 1..iterations {
            if !all_finite(pass.x.as_slice()) {
                break;
            }
            // The stopping test needs only h at the iterate; the AD Jacobians follow only when
            // another pass does (as in `Ekf::update_iterated`).
            let old: Vec<_> = items.iter().map(|(_, it)| *it).collect();
            let values = first.values_at(&pass.x, epoch, beacons, &all_slots);
            if linearization_error_values(&lin, &old, &pass.x, &values) <= RELINEARIZATION_TOLERANCE
            {
                break;
            }
            lin = pass.x;
            items = all_slots
                .iter()
                .copied()
                .zip(first.items_at(&pass.x, epoch, beacons, &all_slots))
                .collect();
            pass = fusion_pass(
                &x,
                &p,
                info.as_ref(),
                &lin,
                &items,
                &masks,
                self.ens.members.len(),
                self.n_consider,
            )?;
        }
        for &i in &pass.failed {
            self.ens.members[i] = None;
        }
        let FusionPass {
            x: xf,
            p: pf,
            weights,
            nis,
            n_meas,
            nis_terms,
            ..
        } = pass;
        for f in self.ens.members.iter_mut().flatten() {
            f.set_estimate(xf, pf);
        }
        self.ens.fused = (xf, pf);
        Ok(StepInfo {
            nis: (n_meas > 0).then_some(nis),
            n_meas,
            innovations: Vec::new(),
            weights: Some(weights),
            nis_terms,
            gate: None,
        })
    }
}

impl<const N: usize> NavFilter<N> for FusionNav<N> {
    fn predict(&mut self, t_to: f64) -> Result<(), EstimationError> {
        if self.feedback {
            return self.predict_shared(t_to);
        }
        self.ens.predict_each(t_to);
        self.ens.alive(LOCAL)
    }

    fn update(
        &mut self,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
    ) -> Result<StepInfo, EstimationError> {
        if self.exact {
            return self.update_exact(epoch, beacons);
        }
        let mut nis = 0.0;
        let mut n_meas = 0;
        let mut nis_terms = Vec::new();
        // With feedback the locals share x̂⁻, so one linearisation serves them all.
        let shared = if self.feedback {
            self.ens
                .first()
                .map(|f| f.all_measurement_items(epoch, beacons))
        } else {
            None
        };
        for slot in self.ens.members.iter_mut() {
            if let Some(f) = slot {
                let result = match &shared {
                    Some(items) => f.update_iterated(items, epoch, beacons),
                    None => f.update(epoch, beacons),
                };
                match result {
                    Ok(info) => {
                        nis += info.nis.unwrap_or(0.0);
                        n_meas += info.n_meas;
                        nis_terms.extend(info.nis_terms);
                    }
                    Err(_) => *slot = None,
                }
            }
        }
        self.ens.alive(LOCAL)?;
        let alive = self.fusing();
        let estimates: Vec<_> = alive
            .iter()
            .filter_map(|&i| self.ens.members[i].as_ref().map(|f| f.estimate()))
            .collect();
        // The optimal weights move little between epochs: start their search from the last ones
        // (uniform at the first epoch, or when none of the fused locals had weight).
        let start: Vec<f64> = alive
            .iter()
            .map(|&i| self.last_weights.get(i).copied().unwrap_or(0.0))
            .collect();
        let fused = covariance_intersection_from(&estimates, self.method, &start)?;
        if self.feedback {
            for (&i, (x, p)) in alive.iter().zip(feedback(&fused)) {
                if let Some(f) = self.ens.members[i].as_mut() {
                    f.set_estimate(x, p);
                }
            }
        }
        let mut weights = vec![0.0; self.ens.members.len()];
        for (&i, w) in alive.iter().zip(&fused.weights) {
            weights[i] = *w;
        }
        self.last_weights.clone_from(&weights);
        self.ens.fused = (fused.x, fused.p);
        Ok(StepInfo {
            nis: Some(nis),
            n_meas,
            innovations: Vec::new(),
            weights: Some(weights),
            nis_terms,
            gate: None,
        })
    }

    /// With information feedback every local filter starts from the fused estimate, so their
    /// common prior is the fused prior. Without feedback (CI) the local priors differ and are
    /// only fused after their updates; the gate then uses the local prior with the smallest
    /// position variance, a consistent (if wider than fused) prior.
    fn prior(&self) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
        let live = self.ens.members.iter().flatten().map(|f| f.estimate());
        if self.feedback {
            return live.into_iter().next().unwrap_or(self.ens.fused);
        }
        live.min_by(|a, b| {
            let pos = |p: &SMatrix<f64, N, N>| (0..3.min(N)).map(|i| p[(i, i)]).sum::<f64>();
            pos(&a.1).total_cmp(&pos(&b.1))
        })
        .unwrap_or(self.ens.fused)
    }

    fn exclude_beacons(&mut self, beacons: &[usize]) {
        self.excluded = beacons.to_vec();
    }

    fn core(&self) -> &dyn FilterCore<N> {
        &self.ens
    }

    fn core_mut(&mut self) -> &mut dyn FilterCore<N> {
        &mut self.ens
    }

    fn density_profile(&self, altitude_m: f64) -> Option<f64> {
        let m = self.ens.first()?.model();
        m.estimated_density_profile(&self.ens.fused.0, altitude_m)
    }
}
