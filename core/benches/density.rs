//! Density-adaptation benchmarks on `msl-airdata` (seed 001): one filter step (predict + update)
//! of UKF-CM, UKF-AC and USKF-NN — for the USKF-NN including the maximum-likelihood adaptation
//! (Algorithm 2) — early in the entry and near peak dynamic pressure; the network's forward and
//! backward passes; and one training epoch over the full Algorithm 1 data set (1000 trajectories).

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use entrynav::estimation::adaptive::{
    Activations, BandedExponential, NetworkFile, builtin_network_toml, fit_onboard_exponential,
    train_network,
};
use entrynav::estimation::nav::{FilterKind, FilterStart, build_filter};
use entrynav::scenario::{DensityTrainingConfig, Scenario, ScenarioConfig};
use entrynav::sim::density::training::generate_data;
use entrynav::sim::engine::start::initial_estimate;
use entrynav::sim::{run_seed, simulate_truth};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;
use std::sync::Arc;

fn bench(c: &mut Criterion) {
    let cfg = ScenarioConfig::builtin("msl-airdata").unwrap();
    let s = Arc::new(Scenario::build(cfg, &entrynav::files::no_files).unwrap());
    let mut rng = ChaCha8Rng::seed_from_u64(run_seed(1, 0));
    let draw = s.draw_truth(&mut rng);
    let truth = simulate_truth(&s, &draw, &mut rng).unwrap();
    let x0 = initial_estimate(&s, &draw, &truth.samples[0], &mut rng);
    let start = FilterStart::<8>::with_estimate(&s.onboard, &x0);
    for kind in [FilterKind::UskfNn, FilterKind::UkfAc, FilterKind::UkfCm] {
        // k = 60 (15 s, 100 km, adaptation still busy) and k = 300 (75 s, near peak pressure).
        for k in [60usize, 300] {
            let mut f = build_filter::<8, 9>(kind, &s.onboard, &start).unwrap();
            for e in &truth.epochs[..k] {
                f.predict(e.t).unwrap();
                f.update(e, &[]).unwrap();
            }
            let epoch = truth.epochs[k].clone();
            c.bench_function(&format!("{}_step_k{k}", kind.name()), |b| {
                b.iter_batched(
                    || f.clone_box(),
                    |mut g| {
                        g.predict(black_box(epoch.t)).unwrap();
                        g.update(black_box(&epoch), &[]).unwrap()
                    },
                    BatchSize::SmallInput,
                )
            });
        }
    }

    let set = NetworkFile::from_toml_str(
        builtin_network_toml("msl-airdata-density-nn.toml").unwrap(),
        "builtin",
    )
    .unwrap()
    .to_set()
    .unwrap();
    let net = set.nets[0].clone();
    let r = s.planet.radius + 60e3;
    c.bench_function("nn_density_1x100x1", |b| {
        b.iter(|| net.density(black_box(r)))
    });
    let mut act = Activations::default();
    let mut g = vec![0.0; net.n_params()];
    c.bench_function("nn_density_gradient_1x100x1", |b| {
        b.iter(|| net.density_gradient(black_box(r), 1.0, &mut g, &mut act))
    });

    // One epoch of Algorithm 1's training over the default data set (1000 trajectories).
    let tc = DensityTrainingConfig {
        epochs: 1,
        ..s.config.filter.density.clone().unwrap().training
    };
    let exp = fit_onboard_exponential(&s.truth_model.atmosphere, 0.0, 130.0).unwrap();
    let atm = BandedExponential {
        tops_m: vec![130e3],
        models: vec![exp],
    };
    let mut group = c.benchmark_group("training");
    group.sample_size(10);
    group.bench_function("generate_data_1000_trajectories", |b| {
        b.iter(|| generate_data(&s, &atm, &tc))
    });
    let data = generate_data(&s, &atm, &tc);
    group.bench_function("train_one_epoch_1000_trajectories", |b| {
        b.iter(|| train_network(&data, &tc, 1, &|_, _| {}).unwrap())
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
