//! Multiple-model banks of EKFs over density biases: classical MMAE and seed 003's modified
//! mixture of experts.

use super::ekf_nav::EkfNav;
use super::ensemble::EkfEnsemble;
use super::nav_filter::{FilterCore, NavFilter};
use super::start::FilterStart;
use super::step_info::StepInfo;
use crate::dynamics::AugmentedParam;
use crate::estimation::error::EstimationError;
use crate::estimation::mmae::{
    ClassicBank, DEFAULT_ETA, DEFAULT_P_MIN, MixtureOfExperts, fuse_bank,
};
use crate::estimation::model_probability::gaussian_log_likelihood;
use crate::estimation::onboard::Onboard;
use crate::math::V3;
use crate::sensors::Channel;
use crate::sensors::MeasurementEpoch;
use nalgebra::{DMatrix, DVector, SMatrix, SVector};
use std::sync::Arc;

/// Mars mean surface pressure used to normalise dynamic pressure for the gating (seed 003 §3.2) \[Pa\].
pub const MARS_SURFACE_PRESSURE_PA: f64 = 610.0;
/// Heating is not in seed 003; we normalise it by a typical peak stagnation heating rate [W/m²].
pub const HEATING_SCALE_WM2: f64 = 1.0e6;

#[derive(Debug, Clone)]
enum Gate {
    Classic(ClassicBank),
    Moe(MixtureOfExperts),
}

/// A bank of EKFs, model i with density ρ_model·(1 + Δ_i) (seed 003 eq. 6, Table 4).
///
/// Each step every member predicts; its prior innovation ν_i and S_i = H P⁻ Hᵀ + R give
/// ln N(ν_i; 0, S_i); the classical bank updates posterior probabilities by Bayes' rule
/// (floor `DEFAULT_P_MIN`), the mixture of experts gates on the normalised measurement vector
/// (pressure / 610 Pa, acceleration / g0, range / R, range-rate / √(g0 R), eq. 17–25). The output
/// is the probability-weighted mixture of the members' posteriors. A member that fails
/// numerically gets zero likelihood from then on.
///
/// With a density-bias state in the filter (estimated or a consider parameter), member i carries
/// the residual δ_i of its hypothesis: its density is ρ_model·(1 + Δ_i)(1 + δ_i), δ_i starts at 0
/// with the variance of a uniform density over the member's cell of the bank grid
/// ((Δ_{i+1} − Δ_{i−1})/2)²/12 instead of the scenario's prior (the bank spans the prior; each
/// member stands for its cell), and the member reports the total (1 + Δ_i)(1 + δ_i) − 1 to the
/// mixture, so the bank's density-bias estimate is the probability-weighted Δ with its spread.
/// The cell prior presumes Bayesian weights; the MoE gate's are not posteriors, so under the MoE
/// a member that *estimates* δ keeps the full prior (σ_Δ / (1 + Δ_i)) and is consistent on its
/// own (docs/results.md, "MoE consistency"); a consider δ keeps its cell.
#[derive(Debug, Clone)]
pub struct BankNav<const N: usize> {
    /// The members (model i with density bias `deltas[i]`) and their mixture.
    ens: EkfEnsemble<N>,
    deltas: Vec<f64>,
    /// State index of a density-bias state, if the filter has one.
    density_state: Option<usize>,
    gate: Gate,
    weights: Vec<f64>,
}

impl<const N: usize> BankNav<N> {
    /// A bank over `filter.model_bank_density_bias`; `moe` selects the mixture-of-experts gating.
    pub fn new(
        onboard: &Arc<Onboard>,
        start: &FilterStart<N>,
        moe: bool,
    ) -> Result<Self, EstimationError> {
        let deltas = onboard.tuning.model_bank_density_bias.clone();
        if deltas.len() < 2 {
            return Err(EstimationError::InvalidInput(
                "a model bank needs at least two density biases".into(),
            ));
        }
        let density_state = onboard
            .model
            .augmented
            .iter()
            .position(|a| *a == AugmentedParam::DensityBias)
            .map(|k| 6 + k)
            .filter(|&k| k < N);
        let cells = cell_sigmas(&deltas);
        let consider = |k: usize| k + onboard.tuning.n_consider >= N;
        let members = deltas
            .iter()
            .zip(&cells)
            .map(|(d, cell_sigma)| {
                let mut s = start.clone();
                if let Some(k) = density_state {
                    // Bayesian weights (classical bank): member i stands for its cell of the
                    // grid. Gated weights (MoE) are not posteriors, so a member that estimates
                    // δ must be consistent on its own: it keeps the full prior, centred on Δ_i.
                    // A consider δ is never corrected, so there the member keeps its cell.
                    let sigma = if moe && !consider(k) {
                        start.p0[(k, k)].sqrt() / (1.0 + d)
                    } else {
                        *cell_sigma
                    };
                    s.x0[k] = 0.0;
                    s.p0.row_mut(k).fill(0.0);
                    s.p0.column_mut(k).fill(0.0);
                    s.p0[(k, k)] = sigma * sigma;
                }
                EkfNav::new(onboard, &s, None, 1.0 + d)
            })
            .collect::<Result<Vec<_>, _>>()?;
        let n = deltas.len();
        let gate = if moe {
            Gate::Moe(MixtureOfExperts::new(
                n,
                onboard.channels.len(),
                DEFAULT_ETA,
            )?)
        } else {
            Gate::Classic(ClassicBank::new(n, DEFAULT_P_MIN)?)
        };
        Ok(BankNav {
            ens: EkfEnsemble::new(onboard, members, (start.x0, start.p0)),
            deltas,
            density_state,
            gate,
            weights: vec![1.0 / n as f64; n],
        })
    }

    /// The density biases of the members.
    pub fn deltas(&self) -> &[f64] {
        &self.deltas
    }

    /// Member `i`'s estimate with its density-bias residual δ expressed as the total bias
    /// (1 + Δ_i)(1 + δ) − 1 (a linear map of that state, so the covariance row and column scale
    /// by 1 + Δ_i).
    /// The live members' estimates fused with the current model weights.
    fn fuse_members(&self) -> Result<(SVector<f64, N>, SMatrix<f64, N, N>), EstimationError> {
        let (w, est): (Vec<f64>, Vec<_>) = self
            .ens
            .members
            .iter()
            .enumerate()
            .zip(&self.weights)
            .filter_map(|((i, m), w)| m.as_ref().map(|f| (*w, self.member_estimate(i, f))))
            .unzip();
        fuse_bank(&w, &est)
    }

    fn member_estimate(&self, i: usize, f: &EkfNav<N>) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
        let (mut x, mut p) = f.estimate();
        if let Some(k) = self.density_state {
            let g = 1.0 + self.deltas[i];
            x[k] = g * (1.0 + x[k]) - 1.0;
            p.row_mut(k).scale_mut(g);
            p.column_mut(k).scale_mut(g);
        }
        (x, p)
    }

    fn normalised(&self, epoch: &MeasurementEpoch) -> DVector<f64> {
        let onboard = &self.ens.onboard;
        let p = &onboard.model.planet;
        let g0 = p.surface_gravity();
        DVector::from_iterator(
            epoch.values.len(),
            epoch.values.iter().zip(&onboard.channels).map(|(v, spec)| {
                let Some(z) = v else { return 0.0 };
                match spec.channel {
                    Channel::Accel(_) => z / g0,
                    Channel::DynamicPressure => z / MARS_SURFACE_PRESSURE_PA,
                    Channel::Heating => z / HEATING_SCALE_WM2,
                    Channel::Range(_) => z / p.radius,
                    Channel::RangeRate(_) => z / (g0 * p.radius).sqrt(),
                }
            }),
        )
    }
}

impl<const N: usize> NavFilter<N> for BankNav<N> {
    fn predict(&mut self, t_to: f64) -> Result<(), EstimationError> {
        self.ens.predict_each(t_to);
        Ok(())
    }

    fn update(
        &mut self,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
    ) -> Result<StepInfo, EstimationError> {
        let mut loglik = vec![f64::NEG_INFINITY; self.ens.members.len()];
        // Each live member's predicted measurements and innovation covariance, with its prior
        // weight: the mixture's predictive distribution (for the NIS).
        let mut predictive: Vec<(f64, DVector<f64>, DMatrix<f64>)> = Vec::new();
        let mut epoch_slots = Vec::new();
        let prior_weights = self.weights.clone();
        for (i, slot) in self.ens.members.iter_mut().enumerate() {
            let Some(f) = slot else { continue };
            let (slots, items) = f.measurement_items(epoch, beacons);
            if items.is_empty() {
                loglik[i] = 0.0;
                continue;
            }
            let (_, p) = f.estimate();
            let m = items.len();
            let nu = DVector::from_iterator(m, items.iter().map(|(h0, _, z, _)| z - h0));
            let s = DMatrix::from_fn(m, m, |a, b| {
                let v = items[a].1.dot(&(p * items[b].1));
                if a == b { v + items[a].3 } else { v }
            });
            loglik[i] = gaussian_log_likelihood(&nu, &s).unwrap_or(f64::NEG_INFINITY);
            let h0 = DVector::from_iterator(m, items.iter().map(|(h0, _, _, _)| *h0));
            predictive.push((prior_weights[i], h0, s));
            epoch_slots = slots;
            if f.update(epoch, beacons).is_err() {
                *slot = None;
                loglik[i] = f64::NEG_INFINITY;
            }
        }
        self.ens.alive("bank member")?;
        let z = self.normalised(epoch);
        self.weights = match &mut self.gate {
            Gate::Classic(b) => b.update(&loglik)?.to_vec(),
            Gate::Moe(m) => m.update(&z, &loglik)?.1,
        };
        self.ens.fused = self.fuse_members()?;
        let (nis, innovations, nis_terms) = mixture_nis(epoch, &epoch_slots, &predictive);
        Ok(StepInfo {
            nis,
            n_meas: epoch.values.iter().flatten().count(),
            innovations,
            weights: Some(self.weights.clone()),
            nis_terms,
            gate: None,
        })
    }

    /// The members' priors fused with the current model weights, as the update fuses posteriors.
    fn prior(&self) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
        self.fuse_members().unwrap_or(self.ens.fused)
    }

    fn core(&self) -> &dyn FilterCore<N> {
        &self.ens
    }

    fn core_mut(&mut self) -> &mut dyn FilterCore<N> {
        &mut self.ens
    }

    /// The onboard density times the probability-weighted factor of the members' hypotheses
    /// (and their residual density-bias estimates).
    fn density_profile(&self, altitude_m: f64) -> Option<f64> {
        let f = self.ens.first()?;
        let factor: f64 = self
            .ens
            .members
            .iter()
            .zip(self.weights.iter().zip(&self.deltas))
            .map(|(m, (w, d))| {
                let residual = match (m, self.density_state) {
                    (Some(f), Some(k)) => f.estimate().0[k],
                    _ => 0.0,
                };
                w * (1.0 + d) * (1.0 + residual)
            })
            .sum();
        Some(crate::atmosphere::Atmosphere::density(&f.model().atmosphere, altitude_m) * factor)
    }
}

/// Per member, 1σ of a uniform density over its cell of the bank grid: the cell spans half-way to
/// each neighbour (a grid end mirrors its one neighbour).
fn cell_sigmas(deltas: &[f64]) -> Vec<f64> {
    let mut order: Vec<usize> = (0..deltas.len()).collect();
    order.sort_by(|&a, &b| deltas[a].total_cmp(&deltas[b]));
    let mut out = vec![0.0; deltas.len()];
    for (j, &i) in order.iter().enumerate() {
        let left = j.checked_sub(1).map(|l| deltas[i] - deltas[order[l]]);
        let right = order.get(j + 1).map(|&r| deltas[r] - deltas[i]);
        let (l, r) = match (left, right) {
            (Some(l), Some(r)) => (l, r),
            (Some(l), None) => (l, l),
            (None, Some(r)) => (r, r),
            (None, None) => (0.0, 0.0),
        };
        out[i] = ((l + r) / 2.0 / 12f64.sqrt()).max(1e-6);
    }
    out
}

/// NIS of a bank's mixture predictive distribution over the channels `slots` of `epoch`: with
/// member predictions ẑ_i, innovation covariances S_i and prior weights w_i (renormalised over
/// the live members), ẑ = Σ w_i ẑ_i and S = Σ w_i (S_i + (ẑ_i − ẑ)(ẑ_i − ẑ)ᵀ), the moment-matched
/// mixture (Bar-Shalom, Li & Kirubarajan, *Estimation with Applications to Tracking and
/// Navigation*, §11.6). Returns νᵀS⁻¹ν, ν, and the per-channel marginals ν_j²/S_jj; `None` and
/// nothing when no channel was measured or S is not positive definite.
fn mixture_nis(
    epoch: &MeasurementEpoch,
    slots: &[usize],
    members: &[(f64, DVector<f64>, DMatrix<f64>)],
) -> (Option<f64>, Vec<f64>, Vec<(usize, f64)>) {
    let m = slots.len();
    let total: f64 = members.iter().map(|(w, _, _)| w).sum();
    if m == 0 || members.is_empty() || total.is_nan() || total <= 0.0 {
        return (None, Vec::new(), Vec::new());
    }
    let z = DVector::from_iterator(m, slots.iter().map(|&c| epoch.values[c].unwrap_or(0.0)));
    let mut mean = DVector::zeros(m);
    for (w, h, _) in members {
        mean += h * (w / total);
    }
    let mut s = DMatrix::zeros(m, m);
    for (w, h, si) in members {
        let d = h - &mean;
        s += (si + &d * d.transpose()) * (w / total);
    }
    let nu = z - mean;
    let Some(chol) = s.clone().cholesky() else {
        return (None, Vec::new(), Vec::new());
    };
    let nis = nu.dot(&chol.solve(&nu));
    let terms = slots
        .iter()
        .enumerate()
        .map(|(j, &c)| (c, nu[j] * nu[j] / s[(j, j)]))
        .collect();
    (Some(nis), nu.iter().copied().collect(), terms)
}
