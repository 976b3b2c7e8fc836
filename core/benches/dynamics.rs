//! Benchmarks: one RK4 step of the 8-state seed-000 model, its AD Jacobian, the step with its
//! exact (AD through RK4) or linearised (Taylor of e^{hA}) transition matrix, and a full 240 s
//! entry at 0.1 s steps (2400 RK4 steps), spherical and Cartesian.

use criterion::{Criterion, criterion_group, criterion_main};
use entrynav::scenario::{Scenario, ScenarioConfig};
use nalgebra::SVector;
use std::hint::black_box;

fn scenario(name: &str) -> Scenario {
    Scenario::build(
        ScenarioConfig::builtin(name).unwrap(),
        &entrynav::files::no_files,
    )
    .unwrap()
}

fn bench(c: &mut Criterion) {
    let s = scenario("four-beacon-fusion");
    let m = s.filter_model(); // 8 states: r, lon, lat, v, fpa, heading, rho0, L/D
    let x8 = SVector::<f64, 8>::from_iterator(s.onboard.initial_estimate.iter().copied());
    c.bench_function("rk4_step_8state_spherical", |b| {
        b.iter(|| m.step(black_box(&x8), 0.0, 0.1))
    });
    c.bench_function("ad_jacobian_8state_spherical", |b| {
        b.iter(|| m.jacobian(black_box(&x8), 0.0))
    });
    c.bench_function("rk4_step_exact_stm_8state_spherical", |b| {
        b.iter(|| m.step_with_stm(black_box(&x8), 0.0, 1.0))
    });
    c.bench_function("rk4_step_linear_stm_8state_spherical", |b| {
        b.iter(|| m.step_with_linear_stm(black_box(&x8), 0.0, 1.0))
    });

    let truth = &s.truth_model;
    let x6 = s.truth_initial;
    c.bench_function("entry_240s_0p1s_spherical", |b| {
        b.iter(|| {
            let mut x = black_box(x6);
            for _ in 0..2400 {
                x = truth.step(&x, 0.0, 0.1);
            }
            x
        })
    });
    c.bench_function("entry_240s_0p1s_8state_spherical", |b| {
        b.iter(|| {
            let mut x = black_box(x8);
            for _ in 0..2400 {
                x = m.step(&x, 0.0, 0.1);
            }
            x
        })
    });

    let sc = scenario("orbiters-3");
    let xc = sc.truth_initial;
    c.bench_function("entry_240s_0p1s_cartesian", |b| {
        b.iter(|| {
            let mut x = black_box(xc);
            for _ in 0..2400 {
                x = sc.truth_model.step(&x, 0.0, 0.1);
            }
            x
        })
    });
}

criterion_group!(benches, bench);
criterion_main!(benches);
