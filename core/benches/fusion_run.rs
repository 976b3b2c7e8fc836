//! One whole Monte Carlo run of four-beacon-fusion per filter (ekf, ci, dcifaif): the truth and
//! its measurements recorded, then the filter flown over them, i.e. a one-filter trade's cost per
//! run without the PCRLB (`monte_carlo.rs` times the two parts separately). The CI fusion and its
//! weight optimisation make `ci` and `dcifaif` several times the EKF's cost (issue 25).

use criterion::{Criterion, criterion_group, criterion_main};
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav::sim::{filter_run, record_run};
use std::hint::black_box;
use std::sync::Arc;

fn bench(c: &mut Criterion) {
    let name = "four-beacon-fusion";
    let cfg = ScenarioConfig::builtin(name).expect("built-in scenario");
    let s = Arc::new(Scenario::build(cfg, &entrynav::files::no_files).expect("scenario builds"));
    let mut group = c.benchmark_group("whole_run");
    group.sample_size(20);
    for kind in [FilterKind::Ekf, FilterKind::Ci, FilterKind::Dcifaif] {
        group.bench_function(format!("{}_{name}", kind.name()), |b| {
            b.iter(|| {
                let rec = record_run(&s, 1, black_box(0)).expect("truth records");
                filter_run(&s, &s.onboard, &rec, kind)
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
