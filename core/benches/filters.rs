//! Filter step benchmarks on `four-beacon-fusion` (8 states, 3 accelerometer axes + 4 ranges):
//! EKF, UKF and DCIFAIF (4 local EKFs + fast-weight CI + feedback), one predict + update each.

use criterion::{Criterion, criterion_group, criterion_main};
use entrynav::estimation::nav::{FilterKind, build_filter, filter_start};
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav::sim::simulate_truth;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let s = std::sync::Arc::new(
        Scenario::build(
            ScenarioConfig::builtin("four-beacon-fusion").unwrap(),
            &|p| Err(p.to_string()),
        )
        .unwrap(),
    );
    let mut rng = ChaCha8Rng::seed_from_u64(1);
    let draw = s.draw_truth(&mut rng);
    let truth = simulate_truth(&s, &draw, &mut rng).unwrap();
    let start = filter_start::<8>(&s, &draw, &truth.samples[0], &mut rng);
    let epoch = truth.epochs[60].clone();
    let beacons = s.beacon_states(epoch.t);
    for kind in [
        FilterKind::Ekf,
        FilterKind::Ukf,
        FilterKind::Dcifaif,
        FilterKind::Ci,
    ] {
        // Run the filter up to the epoch before, then time one predict + update from a clone-able state.
        let mut f = build_filter::<8>(kind, &s, &start).unwrap();
        for e in &truth.epochs[..60] {
            let b = s.beacon_states(e.t);
            f.predict(e.t).unwrap();
            f.update(e, &b).unwrap();
        }
        let t_prev = truth.epochs[59].t;
        let (x, p) = f.estimate();
        c.bench_function(&format!("{}_step_8state_3accel_4range", kind.name()), |b| {
            b.iter_batched(
                || {
                    let mut g = build_filter::<8>(
                        kind,
                        &s,
                        &entrynav::estimation::nav::FilterStart {
                            x0: x,
                            p0: p,
                            q: start.q,
                        },
                    )
                    .unwrap();
                    g.predict(t_prev).unwrap();
                    g
                },
                |mut g| {
                    g.predict(black_box(epoch.t)).unwrap();
                    g.update(black_box(&epoch), &beacons).unwrap()
                },
                criterion::BatchSize::SmallInput,
            )
        });
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
