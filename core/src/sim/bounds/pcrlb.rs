//! The posterior Cramér–Rao lower bound of a trade's scenario, from its Monte Carlo truth runs.
//!
//! **What is bounded.** The filter's state (same coordinates, units and truth-equivalent values
//! as the RMSE tables, [`truth_in_filter_coords`]) under the scenario's *truth*:
//! the truth's dynamics and atmosphere realisation of each run, the truth's sensors with their
//! true noise, the epochs each run actually had (sensor rates, outages, visibility). The prior is
//! the filter start covariance P0 (the scenario's dispersions where the filter start is drawn
//! from them, `filter.sample_initial_from_p0`); random constants a filter carries (ρ0, L/D,
//! C_D S/m, Δ, accelerometer biases, augmented or consider) are constant states with that prior.
//! The truth has no process noise. Parameters the filter neither estimates nor considers are
//! known to the bound, so a filter that ignores one can fall short of it by more than its own
//! suboptimality.
//!
//! **How.** Per run and epoch k: F_k, the transition from the previous epoch along the truth
//! (RK4 sub-steps of `timing.filter_step_s` with the linearised STM, A = ∂f/∂x by forward AD,
//! [`crate::dynamics::EntryModel::step_with_linear_stm`]), and I_k = Σ_c ∇h_cᵀ∇h_c/σ_c² over the
//! channels measured at k (∇h by AD; relative-noise channels add the Fisher term of their
//! state-dependent variance, 2∇h∇hᵀ/h²). Their run averages F̄_k, Ī_k feed
//! [`crate::pcrlb_recursion`]. Sums are folded in run order and merged in block
//! order, like every other statistic, so shards and thread counts give identical bounds.
//!
//! Position and velocity bounds are √tr(P M) with M the run average of JᵀJ, J the Jacobian of the
//! planet-fixed (spherical states) or inertial (Cartesian states) position or velocity: the bound
//! on the `pos_m`/`vel_mps` RMSE of the tables.

use super::pcrlb_epochs::{BoundRunData, KIN};
use crate::atmosphere::AtmosphereModel;
use crate::dynamics::{AugmentedParam, EntryModel};
use crate::frames::{fixed_to_inertial, spherical_to_fixed};
use crate::math::{Dual, dual_gradient, lift_dual, seed_duals};
use crate::scenario::{Scenario, TruthDraw};
use crate::sensors::Channel;
use crate::sensors::Noise;
use crate::sensors::channels::{kinematics, kinematics_from_motion};
use crate::sim::engine::judge::{kinematic_truth, truth_in_filter_coords};
use crate::sim::engine::{RecordedRun, TruthSample};
use crate::sim::monte_carlo::state_names::state_names;
use crate::state_dim::{DimVisitor, UnsupportedDimension, with_state_dim};
use nalgebra::{SMatrix, SVector};
use std::borrow::Cow;
use thiserror::Error;

/// Why a scenario has no PCRLB (a status of the study, reported beside the tables, not a failure).
#[derive(Debug, Clone, PartialEq, Error)]
pub enum NoBound {
    /// Truth and filter integrate different state spaces (spherical vs Cartesian).
    #[error(
        "the truth flies {truth} dynamics and the filter {filter}: the bound needs one state space"
    )]
    StateSpaces {
        /// The truth's dynamics kind.
        truth: String,
        /// The filter's dynamics kind.
        filter: String,
    },
    /// The filter estimates ρ0 and the truth atmosphere has no reference density to map it to.
    #[error("the filter estimates rho0 but the truth atmosphere has no reference density")]
    NoReferenceDensity,
    /// A filter state has no value in the truth (e.g. a consider state of a model the truth lacks).
    #[error("state {0} has no truth counterpart in this scenario")]
    NoTruthCounterpart(String),
    /// The recorded truth run has no samples.
    #[error("the truth run is empty")]
    EmptyRun,
    /// A channel's noise or gradient is unusable at the truth.
    #[error("channel {channel} has 1-sigma {sigma} or a non-finite gradient at t = {t} s")]
    Channel {
        /// Channel name.
        channel: String,
        /// Its 1-sigma at the truth.
        sigma: f64,
        /// Epoch \[s\].
        t: f64,
    },
    /// The filter dimension is outside the supported range.
    #[error(transparent)]
    Dimension(#[from] UnsupportedDimension),
}

/// What one run contributes to the bound, or why the bound does not exist for the scenario.
pub type BoundRun = Result<BoundRunData, NoBound>;

/// The truth model in the filter's state layout: the run's truth (dynamics, atmosphere
/// realisation, vehicle) with the filter's augmented and consider states, arranged so that at the
/// truth-equivalent state it reproduces the truth exactly (`scenario/truth_values.rs`).
pub(super) fn bound_model(
    scenario: &Scenario,
    draw: &TruthDraw,
) -> Result<EntryModel<AtmosphereModel>, NoBound> {
    let fm = scenario.filter_model();
    let mut m = draw.model.clone();
    if fm.kind != m.kind {
        return Err(NoBound::StateSpaces {
            truth: format!("{:?}", m.kind),
            filter: format!("{:?}", fm.kind),
        });
    }
    let has = |p: AugmentedParam| fm.augmented.contains(&p);
    let density_state = has(AugmentedParam::Rho0) || has(AugmentedParam::DensityBias);
    let same_atmosphere = scenario.config.filter.atmosphere == scenario.config.truth.atmosphere;
    if density_state && !has(AugmentedParam::CdSOverM) {
        // The truth-equivalent density absorbs B_true/B_filter: fly the filter's C_D S/m.
        m.vehicle.cd_s_over_m = fm.vehicle.cd_s_over_m;
    }
    if density_state || (has(AugmentedParam::CdSOverM) && same_atmosphere) {
        m.density_factor = 1.0; // carried by the state
    }
    if has(AugmentedParam::Rho0) {
        m.rho0_model = scenario
            .config
            .truth
            .atmosphere
            .reference_density()
            .ok_or(NoBound::NoReferenceDensity)?;
    }
    m.augmented = fm.augmented.clone();
    m.bias_tau_s = None; // the truth's biases are constants
    Ok(m)
}

/// The bound contributions of one recorded run.
pub fn bound_run(scenario: &Scenario, rec: &RecordedRun) -> BoundRun {
    let n = scenario.onboard.state_dim();
    with_state_dim(n, RunVisitor { scenario, rec })?
}

struct RunVisitor<'a> {
    scenario: &'a Scenario,
    rec: &'a RecordedRun,
}

impl DimVisitor for RunVisitor<'_> {
    type Output = BoundRun;

    fn visit<const N: usize, const L: usize>(self) -> BoundRun {
        let (scenario, rec) = (self.scenario, self.rec);
        let model = bound_model(scenario, &rec.draw)?;
        let truth = TruthStates::<N>::new(scenario, rec)?;
        let bank = scenario.truth_bank;
        let first = rec.truth.samples.first().ok_or(NoBound::EmptyRun)?;
        let (mut t_prev, mut x_prev) = (first.t, truth.at(first));
        let mut out = BoundRunData::with_capacity(N, rec.truth.epochs.len());
        for (epoch, sample) in rec.truth.epochs_with_truth() {
            let phi = transition(scenario, &model, &x_prev, epoch.t - t_prev);
            let x = truth.checked_at(sample)?;
            let (info, (jp, jv)) = information(scenario, &model, &x, epoch, bank)?;
            out.push(
                epoch.t,
                &phi,
                &info,
                &(jp.transpose() * jp),
                &(jv.transpose() * jv),
            );
            (t_prev, x_prev) = (epoch.t, x);
        }
        Ok(out)
    }
}

/// The truth in the filter's state layout along one run: the augmented states are the run's
/// constants (their truth values once per run), the kinematic ones follow the samples.
pub(super) struct TruthStates<'a, const N: usize> {
    scenario: &'a Scenario,
    draw: &'a TruthDraw,
    template: SVector<f64, N>,
}

impl<'a, const N: usize> TruthStates<'a, N> {
    pub(super) fn new(scenario: &'a Scenario, rec: &'a RecordedRun) -> Result<Self, NoBound> {
        let first = rec.truth.samples.first().ok_or(NoBound::EmptyRun)?;
        let x = truth_in_filter_coords(scenario, &rec.draw, first, N);
        if let Some(i) = x.iter().skip(KIN).position(|v| !v.is_finite()) {
            return Err(no_counterpart(scenario, KIN + i));
        }
        Ok(TruthStates {
            scenario,
            draw: &rec.draw,
            template: SVector::<f64, N>::from_column_slice(&x),
        })
    }

    /// The truth state at `sample`.
    pub(super) fn at(&self, sample: &TruthSample) -> SVector<f64, N> {
        let mut x = self.template;
        let kin = kinematic_truth(self.scenario, self.draw, sample);
        for (i, v) in kin.iter().enumerate().take(N.min(KIN)) {
            x[i] = *v;
        }
        x
    }

    /// [`Self::at`], refusing a non-finite state (a state without truth counterpart).
    pub(super) fn checked_at(&self, sample: &TruthSample) -> Result<SVector<f64, N>, NoBound> {
        let x = self.at(sample);
        match x.iter().position(|v| !v.is_finite()) {
            Some(i) => Err(no_counterpart(self.scenario, i)),
            None => Ok(x),
        }
    }
}

fn no_counterpart(scenario: &Scenario, i: usize) -> NoBound {
    let names = state_names(scenario);
    NoBound::NoTruthCounterpart(names.get(i).cloned().unwrap_or_else(|| format!("#{i}")))
}

/// F: the transition over `dt` from the truth state `x_prev`, by RK4 sub-steps of
/// `timing.filter_step_s` with the linearised STM (identity for `dt = 0`).
pub(super) fn transition<const N: usize>(
    scenario: &Scenario,
    model: &EntryModel<AtmosphereModel>,
    x_prev: &SVector<f64, N>,
    dt: f64,
) -> SMatrix<f64, N, N> {
    let mut phi = SMatrix::<f64, N, N>::identity();
    if dt > 0.0 {
        let step = scenario.onboard.filter_step_s;
        let bank = scenario.truth_bank;
        let subs = ((dt / step) - 1e-9).ceil().max(1.0) as usize;
        let h = dt / subs as f64;
        let mut x = *x_prev;
        for k in 0..subs {
            // The last sub-step's state is not needed: the next epoch starts from the recorded
            // truth.
            let f = if k + 1 == subs {
                model.linear_stm(&x, bank, h)
            } else {
                let (x_next, f) = model.step_with_linear_stm(&x, bank, h);
                x = x_next;
                f
            };
            phi = if k == 0 { f } else { f * phi };
        }
    }
    phi
}

/// The tables' position and velocity maps Jₚ, Jᵥ (3×[`KIN`]): planet-fixed for spherical states,
/// inertial for Cartesian ones.
pub(super) type Maps = (SMatrix<f64, 3, KIN>, SMatrix<f64, 3, KIN>);

/// Σ_c ∇h_cᵀ∇h_c/σ_c² (+ the variance term of relative-noise channels) at the truth state `x`,
/// with the tables' position and velocity maps there.
///
/// For spherical states the motion (planet-fixed, then inertial) is differentiated with respect
/// to the six kinematic states only, on which it alone depends, and lifted to all N (the same
/// information as N-variable AD, tested to 1e-12), and the planet-fixed gradients are the maps.
pub(super) fn information<const N: usize>(
    scenario: &Scenario,
    model: &EntryModel<AtmosphereModel>,
    x: &SVector<f64, N>,
    epoch: &crate::sensors::MeasurementEpoch,
    bank: f64,
) -> Result<(SMatrix<f64, N, N>, Maps), NoBound> {
    let xd = seed_duals(x);
    let (kin, maps) = if model.kind.is_cartesian() {
        (kinematics(model, &xd, epoch.t), cartesian_maps())
    } else {
        let x6 = SVector::<f64, KIN>::from_fn(|i, _| x[i]);
        let d6 = seed_duals(&x6);
        let (pf, vf) = spherical_to_fixed(&[d6[0], d6[1], d6[2], d6[3], d6[4], d6[5]]);
        let (pi, vi) = fixed_to_inertial(&pf, &vf, epoch.t, model.omega());
        let lift = |v: &[Dual<KIN>; 3]| v.map(|d| lift_dual::<KIN, N>(&d));
        let kin = kinematics_from_motion(model, &xd, lift(&pi), lift(&vi), xd[3]);
        let mut maps = Maps::default();
        for i in 0..3 {
            maps.0.set_row(i, &dual_gradient(&pf[i]).transpose());
            maps.1.set_row(i, &dual_gradient(&vf[i]).transpose());
        }
        (kin, maps)
    };
    let measured = |c: usize, pred: fn(&Channel) -> bool| {
        epoch.values[c].is_some() && pred(&scenario.channels[c].channel)
    };
    let any = |pred: fn(&Channel) -> bool| (0..epoch.values.len()).any(|c| measured(c, pred));
    // Beacon ephemerides only when a beacon channel is measured at this epoch, the accelerometer
    // triad once for all its axes.
    let beacons = if any(|ch| matches!(ch, Channel::Range(_) | Channel::RangeRate(_))) {
        scenario.beacon_states(epoch.t)
    } else {
        Cow::Borrowed(&[][..])
    };
    let mut triad = None;
    let mut info = SMatrix::<f64, N, N>::zeros();
    for (c, value) in epoch.values.iter().enumerate() {
        if value.is_none() {
            continue;
        }
        let spec = &scenario.channels[c];
        let d = scenario.measurement.evaluate_sharing_triad(
            model,
            &xd,
            &kin,
            bank,
            &beacons,
            spec.channel,
            &mut triad,
        );
        let g = dual_gradient(&d);
        let sigma = spec.noise.sigma(d.re);
        if !(sigma.is_finite() && sigma > 0.0) || g.iter().any(|v| !v.is_finite()) {
            return Err(NoBound::Channel {
                channel: spec.name.clone(),
                sigma,
                t: epoch.t,
            });
        }
        let mut w = sigma.powi(-2);
        if let Noise::Relative(_) = spec.noise {
            w += 2.0 / (d.re * d.re);
        }
        info.ger(w, &g, &g, 1.0);
    }
    Ok((info, maps))
}

/// The 3×[`KIN`] Jacobians of the inertial position and velocity of Cartesian states (the maps
/// of spherical states come out of [`information`]'s AD pass).
fn cartesian_maps() -> Maps {
    let mut pos = SMatrix::<f64, 3, KIN>::zeros();
    let mut vel = SMatrix::<f64, 3, KIN>::zeros();
    for i in 0..3 {
        pos[(i, i)] = 1.0;
        vel[(i, 3 + i)] = 1.0;
    }
    (pos, vel)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::ScenarioConfig;
    use crate::sim::engine::record_run;

    /// The 6-variable AD of the motion lifted to N gives the information matrix and maps of plain
    /// N-variable AD (the spherical path of `information`).
    #[test]
    fn lifted_gradients_equal_full_ad() {
        let cfg = ScenarioConfig::builtin("four-beacon-fusion").unwrap();
        let s = Scenario::build(cfg, &crate::files::no_files).unwrap();
        let rec = record_run(&s, 1, 0).unwrap();
        let model = bound_model(&s, &rec.draw).unwrap();
        for (epoch, sample) in rec.truth.epochs_with_truth().step_by(37) {
            let x = SVector::<f64, 11>::from_column_slice(&truth_in_filter_coords(
                &s, &rec.draw, sample, 11,
            ));
            let (info, (jp, _)) = information(&s, &model, &x, epoch, s.truth_bank).unwrap();
            let xd = seed_duals(&x);
            let kin = kinematics(&model, &xd, epoch.t);
            let beacons = s.beacon_states(epoch.t);
            let mut full = SMatrix::<f64, 11, 11>::zeros();
            for (c, v) in epoch.values.iter().enumerate() {
                if v.is_some() {
                    let spec = &s.channels[c];
                    let d = s.measurement.evaluate_with(
                        &model,
                        &xd,
                        &kin,
                        s.truth_bank,
                        &beacons,
                        spec.channel,
                    );
                    let g = dual_gradient(&d);
                    full += g * g.transpose() / spec.noise.sigma(d.re).powi(2);
                }
            }
            let scale = full.abs().max();
            assert!(
                (info - full).abs().max() <= 1e-12 * scale,
                "t = {}",
                epoch.t
            );
            let x6 = SVector::<f64, KIN>::from_fn(|i, _| x[i]);
            let d6 = seed_duals(&x6);
            let (p, _) = spherical_to_fixed(&[d6[0], d6[1], d6[2], d6[3], d6[4], d6[5]]);
            for (i, pi) in p.iter().enumerate() {
                assert_eq!(jp.row(i).transpose(), dual_gradient(pi));
            }
        }
    }
}
