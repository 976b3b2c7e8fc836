//! Filter step benchmarks on seed 000's scenario (3 accelerometer axes + 4 ranges): EKF, UKF,
//! DCIFAIF (4 local EKFs + fast-weight CI + feedback) and CI (4 local EKFs + det-optimal
//! weights): one predict + update each, from a filter state 60 s into a real run; on
//! `four-beacon-fusion-paper` (the paper's 8 states, one EKF linearisation) and
//! `four-beacon-fusion` (11 states with the accelerometer biases, iterated EKF update).

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use entrynav::estimation::nav::{FilterKind, FilterStart, build_filter};
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav::sim::engine::start::initial_estimate;
use entrynav::sim::simulate_truth;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;
use std::sync::Arc;

fn bench_scenario<const N: usize, const L: usize>(c: &mut Criterion, name: &str) {
    let cfg = ScenarioConfig::builtin(name).unwrap();
    let s = Arc::new(Scenario::build(cfg, &entrynav::files::no_files).unwrap());
    assert_eq!(s.onboard.state_dim(), N, "{name}");
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let draw = s.draw_truth(&mut rng);
    let truth = simulate_truth(&s, &draw, &mut rng).unwrap();
    let x0 = initial_estimate(&s, &draw, &truth.samples[0], &mut rng);
    let start = FilterStart::<N>::with_estimate(&s.onboard, &x0);
    let epoch = truth.epochs[60].clone();
    let beacons = s.beacon_states(epoch.t);
    for kind in [
        FilterKind::Ekf,
        FilterKind::Ukf,
        FilterKind::Dcifaif,
        FilterKind::Ci,
    ] {
        let mut f = build_filter::<N, L>(kind, &s.onboard, &start).unwrap();
        for e in &truth.epochs[..60] {
            let b = s.beacon_states(e.t);
            f.predict(e.t).unwrap();
            f.update(e, &b).unwrap();
        }
        c.bench_function(&format!("{}_step_{name}_{N}state", kind.name()), |b| {
            b.iter_batched(
                || f.clone_box(),
                |mut g| {
                    g.predict(black_box(epoch.t)).unwrap();
                    g.update(black_box(&epoch), &beacons).unwrap()
                },
                BatchSize::SmallInput,
            )
        });
    }
}

fn bench(c: &mut Criterion) {
    bench_scenario::<8, 9>(c, "four-beacon-fusion-paper");
    bench_scenario::<11, 12>(c, "four-beacon-fusion");
}

criterion_group!(benches, bench);
criterion_main!(benches);
