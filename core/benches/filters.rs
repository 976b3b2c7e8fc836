//! Filter step benchmarks on `four-beacon-fusion` (8 states, 3 accelerometer axes + 4 ranges):
//! EKF, UKF, DCIFAIF (4 local EKFs + fast-weight CI + feedback) and CI (4 local EKFs +
//! det-optimal weights): one predict + update each, from a filter state 60 s into a real run.

use criterion::{BatchSize, Criterion, criterion_group, criterion_main};
use entrynav::estimation::nav::{FilterKind, FilterStart, build_filter};
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav::sim::simulate_truth;
use entrynav::sim::start::initial_estimate;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;
use std::sync::Arc;

fn bench(c: &mut Criterion) {
    let cfg = ScenarioConfig::builtin("four-beacon-fusion").unwrap();
    let s = Arc::new(Scenario::build(cfg, &entrynav::files::no_files).unwrap());
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let draw = s.draw_truth(&mut rng);
    let truth = simulate_truth(&s, &draw, &mut rng).unwrap();
    let x0 = initial_estimate(&s, &draw, &truth.samples[0], &mut rng);
    let start = FilterStart::<8>::with_estimate(&s.onboard, &x0);
    let epoch = truth.epochs[60].clone();
    let beacons = s.beacon_states(epoch.t);
    for kind in [
        FilterKind::Ekf,
        FilterKind::Ukf,
        FilterKind::Dcifaif,
        FilterKind::Ci,
    ] {
        let mut f = build_filter::<8, 9>(kind, &s.onboard, &start).unwrap();
        for e in &truth.epochs[..60] {
            let b = s.beacon_states(e.t);
            f.predict(e.t).unwrap();
            f.update(e, &b).unwrap();
        }
        c.bench_function(&format!("{}_step_8state_3accel_4range", kind.name()), |b| {
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

criterion_group!(benches, bench);
criterion_main!(benches);
