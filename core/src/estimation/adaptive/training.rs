//! Offline training of the density network: seed 001 Algorithm 1 and §IV.A.1.
//!
//! 1. The onboard model is a least-squares exponential fit (eq. 16) to the truth *mean* profile
//!    ([`fit_onboard_exponential`]; seed 001 fits Mars-GRAM realisations, we replace those
//!    by our mean profile). With bands ([`DensityTrainingConfig::bands_km`], the multi-network
//!    extension of §VI) each band gets its own fit over its altitudes.
//! 2. N trajectories are simulated on that model from initial states and vehicles drawn from
//!    the scenario's dispersions (Table 1), and (r, ρ) is recorded every `sample_interval_s`
//!    for `duration_s` (`sim::density::training::generate_data`, which drives the simulation engine).
//! 3. Densities are transformed by ϱ = √(𝓑 − log₁₀ ρ) (eq. 29, 𝓑 = 0), inputs and outputs are
//!    normalised with the training-set mean and standard deviation (eq. 30–31), the samples
//!    are split into training and validation sets, and a 1-H-1 tanh network (eq. 32–33) is
//!    trained on the mean squared error of the normalised output with Adam (bias-corrected,
//!    β = (0.9, 0.999)) and a cosine learning-rate schedule from `lr_max` to `lr_min`
//!    (seed 001: "a varying learning rate ranging from 1e-6 to 1e-2").
//!
//! Everything is drawn from `seed`: trajectories, split, initial weights (PyTorch's default
//! uniform initialisation) and the mini-batch order. Mini-batch gradients are summed over a
//! fixed number of chunks in chunk order, so the result does not depend on the thread count.

use super::adam::Adam;
use super::config::DensityTrainingConfig;
use super::error::NetworkError;
use super::network::TrainingRecord;
use super::nn::{Activations, DensityNetwork, Normalisation};
use crate::atmosphere::AtmosphereError;
use crate::atmosphere::{Atmosphere, Exponential};
use crate::math::Real;
use rand::seq::SliceRandom;
use rand::{RngExt, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rayon::prelude::*;
use std::time::Instant;

/// Chunks a mini-batch gradient is split into (fixed, for thread-count-independent sums).
const GRAD_CHUNKS: usize = 8;

/// Least-squares exponential fit (eq. 16) to `mean` sampled every 1 km over `[lo_km, hi_km]`.
pub fn fit_onboard_exponential(
    mean: &impl Atmosphere,
    lo_km: f64,
    hi_km: f64,
) -> Result<Exponential, AtmosphereError> {
    let n = ((hi_km - lo_km).floor() as usize).max(1);
    let samples: Vec<(f64, f64)> = (0..=n)
        .map(|k| {
            let h = (lo_km + k as f64 * (hi_km - lo_km) / n as f64) * 1e3;
            (h, mean.density(h))
        })
        .collect();
    Exponential::fit_least_squares(&samples)
}

/// Piecewise-exponential training atmosphere: one exponential per band (`tops_m` = band tops).
#[derive(Debug, Clone)]
pub struct BandedExponential {
    /// Band tops \[m\], increasing; the last band extends upwards, the first downwards.
    pub tops_m: Vec<f64>,
    /// One exponential per band.
    pub models: Vec<Exponential>,
}

impl BandedExponential {
    fn band(&self, h: f64) -> usize {
        let n = self.tops_m.len();
        self.tops_m[..n - 1]
            .iter()
            .position(|&t| h < t)
            .unwrap_or(n - 1)
    }
}

impl Atmosphere for BandedExponential {
    fn density<T: Real>(&self, altitude_m: T) -> T {
        self.models[self.band(altitude_m.re())].density(altitude_m)
    }
}

/// Samples (r, ρ) of the simulated trajectories, with the trajectory index of each sample.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct TrainingData {
    /// Radius \[m\].
    pub r_m: Vec<f64>,
    /// Density of the training model [kg/m³].
    pub rho: Vec<f64>,
    /// Trajectory each sample comes from.
    pub trajectory: Vec<u32>,
}

/// Result of training one network.
#[derive(Debug, Clone)]
pub struct TrainedNetwork {
    /// The network.
    pub network: DensityNetwork,
    /// What happened.
    pub record: TrainingRecord,
    /// Training-set MSE after each epoch.
    pub train_mse_history: Vec<f64>,
}

fn mean_std(v: &[f64]) -> (f64, f64) {
    let n = v.len().max(1) as f64;
    let m = v.iter().sum::<f64>() / n;
    let var = v.iter().map(|x| (x - m) * (x - m)).sum::<f64>() / n;
    (m, var.sqrt().max(1e-300))
}

/// Mean squared error of the normalised output over `idx` (inputs `i`, targets `o`), in parallel
/// over fixed chunks.
fn mse(net: &DensityNetwork, inputs: &[f64], targets: &[f64], idx: &[usize]) -> f64 {
    if idx.is_empty() {
        return 0.0;
    }
    let chunk = idx.len().div_ceil(GRAD_CHUNKS).max(1);
    let parts: Vec<f64> = idx
        .par_chunks(chunk)
        .map(|c| {
            c.iter()
                .map(|&k| (net.output(inputs[k]) - targets[k]).powi(2))
                .sum::<f64>()
        })
        .collect();
    parts.iter().sum::<f64>() / idx.len() as f64
}

/// Algorithm 1 lines 11–12 on `data`: transform, split, normalise, train. `seed` drives the split,
/// the initial weights and the batch order. `progress(epoch, train_mse)` is called after every
/// epoch.
pub fn train_network(
    data: &TrainingData,
    cfg: &DensityTrainingConfig,
    seed: u64,
    progress: &(dyn Fn(usize, f64) + Sync),
) -> Result<TrainedNetwork, NetworkError> {
    let clock = Instant::now();
    let n = data.r_m.len();
    if n < 10 {
        return Err(NetworkError::TooFewSamples(n));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut order: Vec<usize> = (0..n).collect();
    order.shuffle(&mut rng);
    let n_val = ((n as f64 * cfg.validation_fraction).round() as usize).clamp(1, n - 1);
    let (val_idx, train_idx) = order.split_at(n_val);
    let mut train_idx = train_idx.to_vec();
    let val_idx = val_idx.to_vec();

    // eq. 29–31.
    let shift = 0.0;
    let varrho: Vec<f64> = data
        .rho
        .iter()
        .map(|&r| (shift - r.log10()).max(0.0).sqrt())
        .collect();
    let train_r: Vec<f64> = train_idx.iter().map(|&k| data.r_m[k]).collect();
    let train_q: Vec<f64> = train_idx.iter().map(|&k| varrho[k]).collect();
    let (r_mean, r_std) = mean_std(&train_r);
    let (q_mean, q_std) = mean_std(&train_q);
    let norm = Normalisation {
        r_mean_m: r_mean,
        r_std_m: r_std,
        out_mean: q_mean,
        out_std: q_std,
        shift,
    };
    let inputs: Vec<f64> = data.r_m.iter().map(|r| (r - r_mean) / r_std).collect();
    let targets: Vec<f64> = varrho.iter().map(|q| (q - q_mean) / q_std).collect();

    let h = cfg.hidden;
    let xi = initial_parameters(h, &mut rng);
    let mut net = DensityNetwork::new(h, xi, norm)?;
    let mut adam = Adam::new(net.n_params(), 0.9, 0.999, 1e-8, true);
    let batch = cfg.batch_size.min(train_idx.len()).max(1);
    let mut history = Vec::with_capacity(cfg.epochs);
    let np = net.n_params();
    for epoch in 0..cfg.epochs {
        let lr = cosine_learning_rate(cfg, epoch);
        train_idx.shuffle(&mut rng);
        let mut sum_sq = 0.0;
        for mb in train_idx.chunks(batch) {
            let parts = batch_gradients(&net, mb, &inputs, &targets);
            let mut g = vec![0.0; np];
            for (pg, sq) in &parts {
                g.iter_mut().zip(pg).for_each(|(a, b)| *a += b);
                sum_sq += sq;
            }
            adam.step(net.params_mut(), &g, lr);
        }
        let train_mse = sum_sq / train_idx.len() as f64;
        history.push(train_mse);
        progress(epoch + 1, train_mse);
    }
    train_idx.sort_unstable();
    let train_mse = mse(&net, &inputs, &targets, &train_idx);
    let val_mse = mse(&net, &inputs, &targets, &val_idx);
    let (percentiles, below) = validation_errors(&net, data, &val_idx);
    let trajectories = data
        .trajectory
        .iter()
        .map(|&t| t as usize + 1)
        .max()
        .unwrap_or(0);
    Ok(TrainedNetwork {
        record: TrainingRecord {
            scenario: String::new(),
            seed,
            trajectories,
            train_samples: train_idx.len(),
            validation_samples: val_idx.len(),
            epochs: cfg.epochs,
            batch_size: batch,
            train_mse,
            validation_mse: val_mse,
            validation_rel_err_p50_p99_max: percentiles,
            validation_frac_below_1pct: below,
            wall_time_s: clock.elapsed().as_secs_f64(),
        },
        network: net,
        train_mse_history: history,
    })
}

/// PyTorch's default initialisation of a 1-`h`-1 network: U(±1/√fan_in), the 2h input-layer
/// parameters first, then the h + 1 output-layer ones.
fn initial_parameters(h: usize, rng: &mut ChaCha8Rng) -> Vec<f64> {
    let mut xi = Vec::with_capacity(3 * h + 1);
    for _ in 0..2 * h {
        xi.push(rng.random_range(-1.0..1.0));
    }
    let s2 = 1.0 / (h as f64).sqrt();
    for _ in 0..=h {
        xi.push(rng.random_range(-s2..s2));
    }
    xi
}

/// The cosine-annealed learning rate of `epoch`, from `cfg.lr_max` down to `cfg.lr_min`.
fn cosine_learning_rate(cfg: &DensityTrainingConfig, epoch: usize) -> f64 {
    if cfg.epochs > 1 {
        let c = (std::f64::consts::PI * epoch as f64 / (cfg.epochs - 1) as f64).cos();
        cfg.lr_min + 0.5 * (cfg.lr_max - cfg.lr_min) * (1.0 + c)
    } else {
        cfg.lr_max
    }
}

/// The MSE gradient of the minibatch `mb` and its squared errors, in [`GRAD_CHUNKS`] parallel
/// parts (in chunk order; the caller sums them in that order).
fn batch_gradients(
    net: &DensityNetwork,
    mb: &[usize],
    inputs: &[f64],
    targets: &[f64],
) -> Vec<(Vec<f64>, f64)> {
    let np = net.n_params();
    let chunk = mb.len().div_ceil(GRAD_CHUNKS).max(1);
    mb.par_chunks(chunk)
        .map(|c| {
            let mut g = vec![0.0; np];
            let mut act = Activations::default();
            let mut sq = 0.0;
            let scale = 2.0 / mb.len() as f64;
            for &k in c {
                let i = inputs[k];
                let o = net.forward(i, &mut act);
                let e = o - targets[k];
                sq += e * e;
                net.backward_output(i, scale * e, &mut g, &act);
            }
            (g, sq)
        })
        .collect()
}

/// The relative density errors of the trained network on the validation samples: their 50th,
/// 99th and 100th percentiles and the fraction below 1 %.
fn validation_errors(
    net: &DensityNetwork,
    data: &TrainingData,
    val_idx: &[usize],
) -> ([f64; 3], f64) {
    let mut rel: Vec<f64> = val_idx
        .iter()
        .map(|&k| (net.density(data.r_m[k]) - data.rho[k]).abs() / data.rho[k])
        .collect();
    rel.sort_by(f64::total_cmp);
    let pct = |p: f64| rel[((rel.len() - 1) as f64 * p).round() as usize];
    let below = rel.iter().filter(|&&e| e < 0.01).count() as f64 / rel.len() as f64;
    ([pct(0.5), pct(0.99), pct(1.0)], below)
}
