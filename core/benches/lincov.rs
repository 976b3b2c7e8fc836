//! LinCov of the EKF along the nominal trajectory (`entry_lincov`) against one Monte Carlo run of
//! the same filter (truth and measurements + the EKF over them): issue 25 asks for LinCov of
//! four-beacon-fusion to be ≥ 200× faster than its 1000-run Monte Carlo, i.e. cheaper than five
//! runs.

use criterion::{Criterion, criterion_group, criterion_main};
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav::sim::lincov::entry_lincov;
use entrynav::sim::{filter_run, record_run};
use std::hint::black_box;
use std::sync::Arc;

fn bench(c: &mut Criterion) {
    for name in ["four-beacon-fusion", "msl-pressure"] {
        let cfg = ScenarioConfig::builtin(name).unwrap();
        let s = Arc::new(Scenario::build(cfg, &entrynav::files::no_files).unwrap());
        c.bench_function(&format!("lincov_ekf_{name}"), |b| {
            b.iter(|| entry_lincov(black_box(&s), FilterKind::Ekf).unwrap())
        });
        c.bench_function(&format!("mc_run_ekf_{name}"), |b| {
            b.iter(|| {
                let rec = record_run(black_box(&s), 1, 0).unwrap();
                filter_run(&s, &s.onboard, &rec, FilterKind::Ekf)
            })
        });
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
