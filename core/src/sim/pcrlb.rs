//! The posterior Cramér–Rao lower bound of a trade's scenario, from its Monte Carlo truth runs.
//!
//! **What is bounded.** The filter's state (same coordinates, units and truth-equivalent values
//! as the RMSE tables, [`super::judge::truth_in_filter_coords`]) under the scenario's *truth*:
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
//! [`crate::observability::pcrlb_recursion`]. Sums are folded in run order and merged in block
//! order, like every other statistic, so shards and thread counts give identical bounds.
//!
//! Position and velocity bounds are √tr(P M) with M the run average of JᵀJ, J the Jacobian of the
//! planet-fixed (spherical states) or inertial (Cartesian states) position or velocity: the bound
//! on the `pos_m`/`vel_mps` RMSE of the tables.

use super::judge::truth_in_filter_coords;
use super::monte_carlo::RecordedRun;
use crate::atmosphere::AtmosphereModel;
use crate::beacons::BeaconMotion;
use crate::dynamics::{AugmentedParam, EntryModel};
use crate::frames::spherical_to_fixed;
use crate::math::{dual_gradient, seed_duals};
use crate::scenario::{Scenario, TruthDraw};
use crate::sensors::Noise;
use crate::sensors::channels::kinematics;
use crate::state_dim::{DimVisitor, UnsupportedDimension, with_state_dim};
use nalgebra::{SMatrix, SVector};
use thiserror::Error;

/// One epoch of one run: F, I, JₚᵀJₚ and JᵥᵀJᵥ (each row-major N×N, in that order, in one
/// buffer: one allocation per epoch), with Jₚ, Jᵥ the 3×N position and velocity maps.
#[derive(Debug, Clone, PartialEq)]
pub struct BoundEpoch {
    pub(super) t: f64,
    pub(super) data: Vec<f64>,
}

impl BoundEpoch {
    /// The `k`-th N×N block (0 F, 1 I, 2 JₚᵀJₚ, 3 JᵥᵀJᵥ).
    pub(super) fn block(&self, k: usize) -> &[f64] {
        let n2 = self.data.len() / 4;
        &self.data[k * n2..(k + 1) * n2]
    }
}

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
pub type BoundRun = Result<Vec<BoundEpoch>, NoBound>;

/// The truth model in the filter's state layout: the run's truth (dynamics, atmosphere
/// realisation, vehicle) with the filter's augmented and consider states, arranged so that at the
/// truth-equivalent state it reproduces the truth exactly (`scenario/truth_values.rs`).
fn bound_model(
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
        let names = super::monte_carlo::state_names(scenario);
        let truth_at = |sample| -> Result<SVector<f64, N>, NoBound> {
            let x = truth_in_filter_coords(scenario, &rec.draw, sample, N);
            match x.iter().position(|v| !v.is_finite()) {
                Some(i) => Err(NoBound::NoTruthCounterpart(
                    names.get(i).cloned().unwrap_or_else(|| format!("#{i}")),
                )),
                None => Ok(SVector::from_column_slice(&x)),
            }
        };
        let step = scenario.onboard.filter_step_s;
        let bank = scenario.truth_bank;
        let first = rec.truth.samples.first().ok_or(NoBound::EmptyRun)?;
        let (mut t_prev, mut x_prev) = (first.t, truth_at(first)?);
        let mut out = Vec::with_capacity(rec.truth.epochs.len());
        for (epoch, sample) in rec.truth.epochs_with_truth() {
            let dt = epoch.t - t_prev;
            let mut phi = SMatrix::<f64, N, N>::identity();
            if dt > 0.0 {
                let subs = ((dt / step) - 1e-9).ceil().max(1.0) as usize;
                let h = dt / subs as f64;
                let mut x = x_prev;
                for k in 0..subs {
                    if k + 1 == subs {
                        // The last sub-step's state is not needed: the next epoch starts from
                        // the recorded truth.
                        phi = model.linear_stm(&x, bank, h) * phi;
                    } else {
                        let (x_next, f) = model.step_with_linear_stm(&x, bank, h);
                        phi = f * phi;
                        x = x_next;
                    }
                }
            }
            let x = truth_at(sample)?;
            let info = information(scenario, &model, &x, epoch, bank)?;
            let (jp, jv) = position_velocity_maps(&x, model.kind.is_cartesian());
            let mut data = Vec::with_capacity(4 * N * N);
            for m in [phi, info, jp.transpose() * jp, jv.transpose() * jv] {
                push_row_major(&mut data, &m);
            }
            out.push(BoundEpoch { t: epoch.t, data });
            (t_prev, x_prev) = (epoch.t, x);
        }
        Ok(out)
    }
}

/// Σ_c ∇h_cᵀ∇h_c/σ_c² (+ the variance term of relative-noise channels) at the truth state `x`.
fn information<const N: usize>(
    scenario: &Scenario,
    model: &EntryModel<AtmosphereModel>,
    x: &SVector<f64, N>,
    epoch: &crate::sensors::MeasurementEpoch,
    bank: f64,
) -> Result<SMatrix<f64, N, N>, NoBound> {
    let xd = seed_duals(x);
    let kin = kinematics(model, &xd, epoch.t);
    // Beacon ephemerides only when a beacon channel is measured at this epoch.
    let ranged = epoch.values.iter().enumerate().any(|(c, v)| {
        v.is_some()
            && matches!(
                scenario.channels[c].channel,
                crate::sensors::Channel::Range(_) | crate::sensors::Channel::RangeRate(_)
            )
    });
    let beacons: Vec<_> = if ranged {
        scenario
            .beacons
            .iter()
            .map(|b| b.state_at(epoch.t))
            .collect()
    } else {
        Vec::new()
    };
    let mut info = SMatrix::<f64, N, N>::zeros();
    for (c, value) in epoch.values.iter().enumerate() {
        if value.is_none() {
            continue;
        }
        let spec = &scenario.channels[c];
        let d = scenario
            .measurement
            .evaluate_with(model, &xd, &kin, bank, &beacons, spec.channel);
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
        info += g * g.transpose() * w;
    }
    Ok(info)
}

/// The 3×N Jacobians of the position and velocity the RMSE tables compare.
fn position_velocity_maps<const N: usize>(
    x: &SVector<f64, N>,
    cartesian: bool,
) -> (SMatrix<f64, 3, N>, SMatrix<f64, 3, N>) {
    let mut pos = SMatrix::<f64, 3, N>::zeros();
    let mut vel = SMatrix::<f64, 3, N>::zeros();
    if cartesian {
        for i in 0..3 {
            pos[(i, i)] = 1.0;
            vel[(i, 3 + i)] = 1.0;
        }
        return (pos, vel);
    }
    let x6 = SVector::<f64, 6>::from_fn(|i, _| x[i]);
    let xd = seed_duals(&x6);
    let (p, v) = spherical_to_fixed(&[xd[0], xd[1], xd[2], xd[3], xd[4], xd[5]]);
    for i in 0..3 {
        let (gp, gv) = (dual_gradient(&p[i]), dual_gradient(&v[i]));
        for j in 0..6 {
            pos[(i, j)] = gp[j];
            vel[(i, j)] = gv[j];
        }
    }
    (pos, vel)
}

fn push_row_major<const N: usize>(out: &mut Vec<f64>, m: &SMatrix<f64, N, N>) {
    out.extend((0..N).flat_map(|i| (0..N).map(move |j| m[(i, j)])));
}
