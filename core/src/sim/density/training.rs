//! Seed 001 Algorithm 1, the parts that need a scenario: the training trajectories (lines 1–10),
//! flown by the engine's truth propagator on the training atmosphere, and the whole offline
//! training of one network per altitude band. The network itself and its fitting are in
//! [`crate::estimation::adaptive`].

use crate::atmosphere::Atmosphere;
use crate::dynamics::EntryModel;
use crate::estimation::adaptive::{
    BandedExponential, DensityTrainingConfig, NETWORK_FORMAT, NetworkError, NetworkFile,
    NetworkRecord, TrainingData, fit_onboard_exponential, train_network,
};
use crate::scenario::Scenario;
use crate::sim::engine::TruthPropagator;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;

/// Algorithm 1 lines 1–10: simulate `cfg.trajectories` entries of `scenario` (initial state and
/// vehicle dispersed as the truth, no process noise) on `atmosphere`, recording (r, ρ) every
/// `cfg.sample_interval_s` from t = 0 to `cfg.duration_s` (a trajectory that reaches the
/// ground stops there; the scenario's stop speed does not apply). Trajectory j draws from
/// `ChaCha8(seed ⊕ j)`.
pub fn generate_data(
    scenario: &Scenario,
    atmosphere: &BandedExponential,
    cfg: &DensityTrainingConfig,
) -> TrainingData {
    let step = scenario.config.timing.truth_step_s;
    let per_sample = (cfg.sample_interval_s / step).round().max(1.0) as usize;
    let n_steps = (cfg.duration_s / step).round() as usize;
    let runs: Vec<Vec<(f64, f64)>> = (0..cfg.trajectories)
        .into_par_iter()
        .map(|j| {
            let mut rng = ChaCha8Rng::seed_from_u64(
                cfg.seed ^ (0x9E37_79B9_7F4A_7C15_u64.wrapping_mul(j as u64 + 1)),
            );
            let draw = scenario.draw_truth_run(j, &mut rng);
            let model = EntryModel {
                kind: draw.model.kind,
                planet: draw.model.planet,
                atmosphere: atmosphere.clone(),
                vehicle: draw.model.vehicle,
                augmented: vec![],
                rho0_model: 1.0,
                density_factor: 1.0,
                bias_tau_s: None,
            };
            let mut out = Vec::with_capacity(n_steps / per_sample + 1);
            let mut record = |k: usize, x: &nalgebra::SVector<f64, 6>| {
                let h = model.altitude(x);
                if h < 0.0 || !h.is_finite() {
                    return false;
                }
                if k % per_sample == 0 {
                    out.push((h + model.planet.radius, model.atmosphere.density(h)));
                }
                true
            };
            let mut truth = TruthPropagator::new(draw.initial, step, n_steps, None);
            if record(0, truth.state()) {
                while truth.steps() < n_steps {
                    let Ok(Some(s)) = truth.step(&model, scenario.truth_bank) else {
                        break;
                    };
                    if !record(s.k, &s.x) || s.stop.is_some() {
                        break;
                    }
                }
            }
            out
        })
        .collect();
    let mut data = TrainingData::default();
    for (j, run) in runs.iter().enumerate() {
        for &(r, rho) in run {
            data.r_m.push(r);
            data.rho.push(rho);
            data.trajectory.push(j as u32);
        }
    }
    data
}

/// The whole of Algorithm 1 for `scenario`: fit, simulate, train one network per band (one band
/// when `cfg.bands_km` is empty), and return the network file. `progress(band, epoch, mse)` is
/// called after every epoch.
pub fn train_density_networks(
    scenario: &Scenario,
    cfg: &DensityTrainingConfig,
    progress: &(dyn Fn(usize, usize, f64) + Sync),
) -> Result<(NetworkFile, BandedExponential), NetworkError> {
    let mean = &scenario.truth_model.atmosphere;
    let [lo, hi] = cfg.fit_altitude_km;
    let edges: Vec<f64> = if cfg.bands_km.is_empty() {
        vec![lo, hi]
    } else {
        cfg.bands_km.clone()
    };
    let mut models = Vec::new();
    for w in edges.windows(2) {
        models.push(fit_onboard_exponential(mean, w[0], w[1])?);
    }
    let atmosphere = BandedExponential {
        tops_m: edges[1..].iter().map(|e| e * 1e3).collect(),
        models,
    };
    let data = generate_data(scenario, &atmosphere, cfg);
    let mut networks = Vec::new();
    let nb = atmosphere.models.len();
    for b in 0..nb {
        // A band's network learns its band plus a 2 km margin each side (its own exponential).
        let (blo, bhi) = (edges[b] * 1e3 - 2e3, edges[b + 1] * 1e3 + 2e3);
        let exp = atmosphere.models[b];
        let mut d = TrainingData::default();
        for k in 0..data.r_m.len() {
            let h = data.r_m[k] - scenario.planet.radius;
            if nb == 1 || (h >= blo && h <= bhi) || (b == 0 && h < blo) || (b == nb - 1 && h > bhi)
            {
                d.r_m.push(data.r_m[k]);
                d.rho.push(exp.density(h));
                d.trajectory.push(data.trajectory[k]);
            }
        }
        let seed = cfg.seed.wrapping_add(1_000_003 * b as u64);
        let mut t = train_network(&d, cfg, seed, &|e, m| progress(b, e, m))?;
        t.record.scenario = scenario.config.name.clone();
        t.record.trajectories = cfg.trajectories;
        networks.push(NetworkRecord::from_network(
            &t.network,
            [edges[b], edges[b + 1]],
            [exp.rho_ref, exp.h_ref / 1e3, exp.scale_height / 1e3],
            t.record,
        ));
    }
    let description = if nb == 1 {
        format!(
            "Seed 001 density network (1-{}-1 tanh) for scenario '{}', trained on the least-squares exponential fit to the truth mean profile over {lo}-{hi} km (Algorithm 1).",
            cfg.hidden, scenario.config.name
        )
    } else {
        format!(
            "Seed 001 density networks (1-{}-1 tanh), one per altitude band {:?} km, for scenario '{}', each trained on the least-squares exponential fit to the truth mean profile over its band (seed 001 Sec. VI extension).",
            cfg.hidden, edges, scenario.config.name
        )
    };
    Ok((
        NetworkFile {
            format: NETWORK_FORMAT.to_string(),
            description,
            planet_radius_m: scenario.planet.radius,
            networks,
        },
        atmosphere,
    ))
}
