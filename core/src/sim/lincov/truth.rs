//! The truth side of the entry LinCov: the nominal truth run, its noise-free measurements, and
//! their sensitivities to the truth's random parameters θ by central differences of whole truth
//! runs (Maybeck vol. 1 §6.3's "truth model" reduced to constants: the truth flies no process
//! noise, so its dispersion at epoch k is δx_k = S_k θ with S_k = ∂x_k/∂θ, and its measurement
//! dispersion δz_k = Z_k θ).
//!
//! θ are the standard normals [`Scenario::disperse_with`] turns into a Monte Carlo draw (initial
//! state, C_D S/m, L/D, density bias Δ) and those of the truth's density perturbation, so
//! Cov θ = I. A parameter that cannot move the truth (σ zero, a grid point above the trajectory)
//! is left out.

use super::error::EntryLinCovError;
use crate::atmosphere::{AtmosphereModel, Perturbed};
use crate::math::wrap_pi;
use crate::scenario::{Scenario, TruthDraw};
use crate::sensors::MeasurementEpoch;
use crate::sensors::channels::kinematics;
use crate::sim::engine::TruthSample;
use crate::sim::engine::judge::truth_in_filter_coords;
use crate::sim::engine::simulate_truth;
use nalgebra::{DMatrix, DVector, SVector};
use rand::SeedableRng;

/// Central-difference step of every θ (standard-normal units: 1 % of the dispersion σ). The
/// truth is a fixed-step RK4 integration, smooth in θ; the O(h²) truncation of a 0.01σ step is
/// far below the first-order model error LinCov makes anyway.
const FD_STEP: f64 = 1e-2;

/// One measurement of the nominal truth at an epoch.
#[derive(Debug, Clone)]
pub(super) struct TruthMeasurement {
    /// Channel slot.
    pub slot: usize,
    /// ∂z/∂θ (one entry per parameter).
    pub zeta: DVector<f64>,
    /// The truth's noise variance at z̄.
    pub r: f64,
}

/// The nominal truth at one measurement epoch.
#[derive(Debug, Clone)]
pub(super) struct TruthEpoch {
    /// Epoch time \[s\].
    pub t: f64,
    /// Truth in the filter's coordinates (NaN: no truth counterpart).
    pub x: Vec<f64>,
    /// S = ∂x/∂θ (N × p).
    pub s: DMatrix<f64>,
    /// The channels available at this epoch in the nominal run.
    pub meas: Vec<TruthMeasurement>,
    /// The epoch as the filter receives it, noise-free.
    pub epoch: MeasurementEpoch,
}

/// The nominal truth with its sensitivities.
#[derive(Debug, Clone)]
pub(super) struct NominalTruth {
    /// Names of the parameters θ.
    pub params: Vec<String>,
    /// Truth in filter coordinates at t = 0 and its sensitivity.
    pub x0: Vec<f64>,
    /// ∂x_0/∂θ.
    pub s0: DMatrix<f64>,
    /// The measurement epochs.
    pub epochs: Vec<TruthEpoch>,
    /// The first nominal epoch \[s\] dropped because a ±h run ended before it.
    pub truncated: Option<f64>,
}

/// The truth realisation with standard normal θ_j set to `dz` and every other one zero: the draw's
/// normals ([`Scenario::disperse_with`]) first, then, when the truth has a density
/// perturbation, one per point of its AR(1) grid ([`Perturbed::from_normals`]).
fn draw_with(scenario: &Scenario, j: Option<usize>, dz: f64) -> TruthDraw {
    let at = |i: usize| if Some(i) == j { dz } else { 0.0 };
    let mut i = 0;
    let mut draw = scenario.disperse_with(|| {
        let v = at(i);
        i += 1;
        v
    });
    if let Some(p) = &scenario.config.truth.perturbation {
        let spec = p.to_spec();
        let first = scenario.dispersion_normals();
        let normals: Vec<f64> = (0..spec.grid_len()).map(|k| at(first + k)).collect();
        draw.model.atmosphere = AtmosphereModel::Perturbed(Box::new(Perturbed::from_normals(
            draw.model.atmosphere,
            &spec,
            &normals,
        )));
    }
    draw
}

/// Names of θ and whether each can move the truth: a draw normal whose σ is not zero, a grid
/// normal of the density perturbation at or below `top_m` (the highest altitude flown; a grid
/// normal enters the AR(1) values at its altitude and above only).
fn parameters(scenario: &Scenario, top_m: f64) -> Vec<(String, bool)> {
    let d = &scenario.config.dispersions;
    let mut out = Vec::new();
    if scenario.dispersion_normals() == 9 {
        for k in 0..6 {
            out.push((format!("initial_state_{k}"), true));
        }
    }
    out.push(("cd_s_over_m".into(), d.cd_s_over_m_m2kg != 0.0));
    out.push(("lift_to_drag".into(), d.lift_to_drag != 0.0));
    out.push(("density_bias".into(), d.density_bias != 0.0));
    if let Some(p) = &scenario.config.truth.perturbation {
        let spec = p.to_spec();
        let moves = spec.scale > 0.0;
        for k in 0..spec.grid_len() {
            let h = spec.grid_bottom_m + k as f64 * spec.grid_step_m;
            out.push((
                format!("density_perturbation_{:.0}m", h),
                moves && h <= top_m + spec.grid_step_m,
            ));
        }
    }
    out
}

/// Noise-free readings h_t(x) + bias of channels `slots` at the truth sample.
fn readings(scenario: &Scenario, draw: &TruthDraw, s: &TruthSample, slots: &[usize]) -> Vec<f64> {
    let x = SVector::<f64, 6>::from(s.state);
    let kin = kinematics(&draw.model, &x, s.t);
    let beacons = scenario.beacon_states(s.t);
    let mut triad = None;
    slots
        .iter()
        .map(|&c| {
            let spec = &scenario.channels[c];
            scenario.measurement.evaluate_sharing_triad(
                &draw.model,
                &x,
                &kin,
                scenario.truth_bank,
                &beacons,
                spec.channel,
                &mut triad,
            ) + spec.bias
        })
        .collect()
}

/// One truth run: samples at t = 0 and at each epoch, with the epochs.
type Run = (Vec<TruthSample>, Vec<MeasurementEpoch>);

fn run(scenario: &Scenario, draw: &TruthDraw) -> Result<Run, EntryLinCovError> {
    // The noise does not enter (readings are recomputed noise-free); any seed will do.
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(0);
    let truth = simulate_truth(scenario, draw, &mut rng)?;
    let n = truth.epochs.len();
    Ok((truth.samples[..=n].to_vec(), truth.epochs))
}

/// x_a − x_b in filter coordinates, angles wrapped (spherical filters).
fn difference(spherical: bool, a: &[f64], b: &[f64]) -> Vec<f64> {
    let mut d: Vec<f64> = a.iter().zip(b).map(|(x, y)| x - y).collect();
    if spherical && d.len() >= 6 {
        d[1] = wrap_pi(d[1]);
        d[5] = wrap_pi(d[5]);
    }
    d
}

/// Fly the nominal truth and the ±h runs of every dispersed parameter; `n` is the filter
/// dimension.
pub(super) fn nominal_truth(
    scenario: &Scenario,
    n: usize,
) -> Result<NominalTruth, EntryLinCovError> {
    let spherical = !scenario.filter_model().kind.is_cartesian();
    let nominal = draw_with(scenario, None, 0.0);
    let (samples, epochs) = run(scenario, &nominal)?;
    if epochs.is_empty() {
        return Err(EntryLinCovError::NoEpochs(scenario.config.name.clone()));
    }
    let slots: Vec<Vec<usize>> = epochs
        .iter()
        .map(|e| {
            (0..e.values.len())
                .filter(|&c| e.values[c].is_some())
                .collect()
        })
        .collect();
    let in_filter = |d: &TruthDraw, s: &TruthSample| truth_in_filter_coords(scenario, d, s, n);
    let top_m = samples.iter().map(|x| x.altitude).fold(f64::MIN, f64::max);
    let all = parameters(scenario, top_m);
    let active: Vec<usize> = (0..all.len()).filter(|&j| all[j].1).collect();
    let p = active.len();
    let mut k_max = epochs.len();
    let mut s_mats = vec![DMatrix::<f64>::zeros(n, p); k_max + 1];
    let mut zetas: Vec<Vec<DVector<f64>>> = slots
        .iter()
        .map(|sl| vec![DVector::zeros(p); sl.len()])
        .collect();
    for (col, &j) in active.iter().enumerate() {
        let plus_draw = draw_with(scenario, Some(j), FD_STEP);
        let minus_draw = draw_with(scenario, Some(j), -FD_STEP);
        let plus = run(scenario, &plus_draw)?.0;
        let minus = run(scenario, &minus_draw)?.0;
        // A dispersed run may stop a step earlier (ground, stop speed): keep the common epochs.
        k_max = k_max.min(plus.len() - 1).min(minus.len() - 1);
        for k in 0..=k_max {
            let (sp, sm) = (&plus[k], &minus[k]);
            if (sp.t - samples[k].t).abs() > 1e-9 || (sm.t - samples[k].t).abs() > 1e-9 {
                return Err(EntryLinCovError::Schedule {
                    parameter: all[j].0.clone(),
                    t: samples[k].t,
                });
            }
            let dx = difference(
                spherical,
                &in_filter(&plus_draw, sp),
                &in_filter(&minus_draw, sm),
            );
            for (i, v) in dx.iter().enumerate() {
                s_mats[k][(i, col)] = if v.is_finite() {
                    v / (2.0 * FD_STEP)
                } else {
                    0.0
                };
            }
            if k > 0 {
                let zp = readings(scenario, &plus_draw, sp, &slots[k - 1]);
                let zm = readings(scenario, &minus_draw, sm, &slots[k - 1]);
                for (m, (a, b)) in zp.iter().zip(&zm).enumerate() {
                    zetas[k - 1][m][col] = (a - b) / (2.0 * FD_STEP);
                }
            }
        }
    }
    let mut out_epochs = Vec::with_capacity(k_max);
    let mut s_iter = s_mats.into_iter();
    let s0 = s_iter.next().unwrap_or_else(|| DMatrix::zeros(n, p));
    for (((epoch, sample), s), (sl, zeta)) in epochs[..k_max]
        .iter()
        .zip(&samples[1..])
        .zip(s_iter)
        .zip(slots.iter().zip(zetas))
    {
        let (filter_epoch, meas) = measurements(scenario, &nominal, epoch, sample, sl, zeta)?;
        out_epochs.push(TruthEpoch {
            t: epoch.t,
            x: in_filter(&nominal, sample),
            s,
            meas,
            epoch: filter_epoch,
        });
    }
    Ok(NominalTruth {
        params: active.iter().map(|&j| all[j].0.clone()).collect(),
        x0: in_filter(&nominal, &samples[0]),
        s0,
        truncated: (k_max < epochs.len()).then(|| epochs[k_max].t),
        epochs: out_epochs,
    })
}

/// The nominal run's epoch `epoch` (truth `sample`) as the filter meets it: the truth's
/// noise-free readings of the channels `slots`, with their sensitivities `zetas` and the truth's
/// noise variances.
fn measurements(
    scenario: &Scenario,
    nominal: &TruthDraw,
    epoch: &MeasurementEpoch,
    sample: &TruthSample,
    slots: &[usize],
    zetas: Vec<DVector<f64>>,
) -> Result<(MeasurementEpoch, Vec<TruthMeasurement>), EntryLinCovError> {
    let values = readings(scenario, nominal, sample, slots);
    let mut filter_epoch = MeasurementEpoch {
        t: epoch.t,
        values: vec![None; epoch.values.len()],
    };
    let mut meas = Vec::with_capacity(slots.len());
    for ((&slot, &value), zeta) in slots.iter().zip(&values).zip(zetas) {
        let sigma = scenario.channels[slot].noise.sigma(value);
        if !(value.is_finite() && sigma.is_finite() && sigma > 0.0)
            || zeta.iter().any(|v| !v.is_finite())
        {
            return Err(EntryLinCovError::NonFinite {
                what: format!("truth channel {}", scenario.channels[slot].name),
                t: epoch.t,
            });
        }
        filter_epoch.values[slot] = Some(value);
        meas.push(TruthMeasurement {
            slot,
            zeta,
            r: sigma * sigma,
        });
    }
    Ok((filter_epoch, meas))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::ScenarioConfig;

    /// The sensitivities predict a dispersed run: for θ_j = 0.05 (a twentieth of a σ) the truth in
    /// filter coordinates and the noise-free measurements of a whole run differ from the nominal
    /// by S θ and Z θ, to first order (the check of the central differences).
    #[test]
    fn sensitivities_predict_a_dispersed_run() {
        let cfg = ScenarioConfig::builtin("msl-pressure-orbiter").unwrap();
        let s = Scenario::build(cfg, &crate::files::no_files).unwrap();
        let n = s.onboard.state_dim();
        let nominal = nominal_truth(&s, n).unwrap();
        let top = f64::INFINITY;
        let all = parameters(&s, top);
        let active: Vec<usize> = (0..all.len()).filter(|&j| all[j].1).collect();
        assert_eq!(active.len(), nominal.params.len());
        let nominal_draw = draw_with(&s, None, 0.0);
        let theta = 0.05;
        for (col, &j) in active.iter().enumerate() {
            let draw = draw_with(&s, Some(j), theta);
            let (samples, _) = run(&s, &draw).unwrap();
            for (k, ep) in nominal.epochs.iter().enumerate().step_by(50) {
                let x = truth_in_filter_coords(&s, &draw, &samples[k + 1], n);
                let actual = difference(false, &x, &ep.x);
                for i in 0..6 {
                    let predicted = ep.s[(i, col)] * theta;
                    let scale = (0..6).map(|r| actual[r].abs()).fold(1e-9, f64::max);
                    assert!(
                        (actual[i] - predicted).abs() <= 0.02 * scale + 1e-9,
                        "{} t = {} state {i}: actual {} predicted {}",
                        all[j].0,
                        ep.t,
                        actual[i],
                        predicted
                    );
                }
                let slots: Vec<usize> = ep.meas.iter().map(|m| m.slot).collect();
                let z = readings(&s, &draw, &samples[k + 1], &slots);
                let z0 = readings(&s, &nominal_draw, &samples_nominal(&s, k + 1), &slots);
                for ((m, zi), z0i) in ep.meas.iter().zip(&z).zip(&z0) {
                    let predicted = m.zeta[col] * theta;
                    let actual = zi - z0i;
                    assert!(
                        (actual - predicted).abs() <= 0.02 * actual.abs().max(1e-12) + 1e-9,
                        "{} t = {} slot {}: actual {actual} predicted {predicted}",
                        all[j].0,
                        ep.t,
                        m.slot
                    );
                }
            }
        }
    }

    fn samples_nominal(s: &Scenario, k: usize) -> TruthSample {
        run(s, &draw_with(s, None, 0.0)).unwrap().0[k].clone()
    }
}
