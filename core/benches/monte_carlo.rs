//! One Monte Carlo run's parts: the truth and its measurements (`record_run`), each filter over
//! it (`filter_run`), and the run's PCRLB contribution (`bound_run`): what the PCRLB adds to a
//! trade's wall time.

use criterion::{Criterion, criterion_group, criterion_main};
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav::sim::bounds::pcrlb::bound_run;
use entrynav::sim::{filter_run, record_run};
use std::hint::black_box;
use std::sync::Arc;

fn bench(c: &mut Criterion) {
    for (name, filters) in [
        (
            "four-beacon-fusion",
            &[FilterKind::Ekf, FilterKind::Ci, FilterKind::Dcifaif][..],
        ),
        (
            "msl-pressure-orbiter",
            &[FilterKind::Ekf, FilterKind::MmaeMoe][..],
        ),
    ] {
        let cfg = ScenarioConfig::builtin(name).unwrap();
        let s = Arc::new(Scenario::build(cfg, &entrynav::files::no_files).unwrap());
        let rec = record_run(&s, 1, 0).unwrap();
        c.bench_function(&format!("record_run_{name}"), |b| {
            b.iter(|| record_run(black_box(&s), 1, 0).unwrap())
        });
        for &kind in filters {
            c.bench_function(&format!("filter_run_{}_{name}", kind.name()), |b| {
                b.iter(|| filter_run(&s, &s.onboard, black_box(&rec), kind))
            });
        }
        c.bench_function(&format!("bound_run_{name}"), |b| {
            b.iter(|| bound_run(&s, black_box(&rec)).unwrap())
        });
    }
}

criterion_group!(benches, bench);
criterion_main!(benches);
