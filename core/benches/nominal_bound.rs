//! The nominal-trajectory position bound per beacon-design candidate (`sim::bounds::nominal_bound`):
//! `ground-beacons-3` (240 range epochs, 6 states) with its three surface beacons, the cost of
//! one candidate in `entrynav optimize ground --objective pcrlb-*` (issue target ≤ 0.2 ms on the
//! project's 2-core machine), and the one-off set-up (nominal truth, STMs, maps).

use criterion::{Criterion, criterion_group, criterion_main};
use entrynav::beacons::Beacon;
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav::sim::bounds::nominal_bound::{NominalBound, RangeSite};
use std::hint::black_box;

fn bench(c: &mut Criterion) {
    let s = Scenario::build(
        ScenarioConfig::builtin("ground-beacons-3").unwrap(),
        &entrynav::files::no_files,
    )
    .unwrap();
    let sites: Vec<RangeSite> = s
        .beacons
        .iter()
        .filter_map(|b| match b {
            Beacon::Surface(b) => Some(RangeSite {
                position_m: b.position_at(0.0),
                sigma_m: 100.0,
                elevation_mask_rad: 0.0,
            }),
            Beacon::Orbiter(_) => None,
        })
        .collect();
    let nominal = NominalBound::new(&s).unwrap();
    c.bench_function("nominal_bound_gb3_candidate_3_sites", |b| {
        b.iter(|| black_box(nominal.ground_sites(black_box(&sites)).unwrap()))
    });
    c.bench_function("nominal_bound_gb3_setup", |b| {
        b.iter(|| black_box(NominalBound::new(black_box(&s)).unwrap()))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
