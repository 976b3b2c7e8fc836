//! Benchmarks of seed 002 Table 3: δ(t) along the `ground-beacons-3` entry (240 s at 1 Hz, 241
//! points, 6 states, 3 range beacons) by the exact Lie-derivative method, the quadratic
//! approximation and the linearisation (each point: observability matrix, raw and scaled SVD).
//! The paper reports > 10,000 s, 2.16 s and 1.40 s. Also the 8-state `four-beacon-fusion`
//! centralised system (300 s, 301 points, order-7 Lie derivatives of 7 channels).

use criterion::{Criterion, criterion_group, criterion_main};
use entrynav::observability::{
    ChannelSet, Method, Scaling, analysis_points, degree_series, max_det_directions,
};
use entrynav::scenario::{Scenario, ScenarioConfig};
use std::hint::black_box;

fn scenario(name: &str) -> Scenario {
    Scenario::build(
        ScenarioConfig::builtin(name).unwrap(),
        &entrynav::files::no_files,
    )
    .unwrap()
}

fn bench(c: &mut Criterion) {
    for (name, label) in [("ground-beacons-3", "gb3"), ("four-beacon-fusion", "fbf")] {
        let s = scenario(name);
        let points = analysis_points(&s, 1.0).unwrap();
        let scaling = Scaling::characteristic(s.filter_model());
        let set = ChannelSet::centralised(&s);
        for method in [Method::Lie, Method::Quadratic, Method::Linear] {
            let id = format!("delta_{label}_{}pts_{}", points.len(), method.name());
            c.bench_function(&id, |b| {
                b.iter(|| degree_series(&s, black_box(&points), &set, method, &scaling).unwrap())
            });
        }
    }
    let s = scenario("ground-beacons-3");
    c.bench_function("analysis_points_gb3_241", |b| {
        b.iter(|| analysis_points(black_box(&s), 1.0).unwrap())
    });
    c.bench_function("max_det_8_directions_6_starts", |b| {
        b.iter(|| max_det_directions(black_box(8), 6, 1))
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
