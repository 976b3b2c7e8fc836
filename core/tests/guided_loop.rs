//! A navigation filter in the guidance loop (issue 28): seed 001's MSL entry (`msl-airdata`) with
//! `[guidance]`, flown with the filter's estimate and the sensed drag fed to guidance, against
//! perfect navigation and the unguided reference bank on the same dispersion draws.

#[path = "support/seed001_guided.rs"]
mod seed001_guided;

use entrynav::estimation::nav::FilterKind;
use entrynav::guidance::GuidanceAlgorithm;
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav::sim::engine::EntryCoSim;
use entrynav::sim::guided::delivery::{DeliveryReport, run_delivery};
use entrynav::sim::run_seed;
use std::sync::Arc;

/// The built-in `msl-guided` as it was before issue 50 (seed 001's dispersions, reference bank
/// 60°, deployment at 450 m/s, no safeguard; `support/seed001_guided.rs`), flown by `algorithm`.
fn msl(algorithm: &str) -> Arc<Scenario> {
    let mut cfg = seed001_guided::seed001_guided_config();
    let g = cfg.guidance.as_mut().unwrap();
    g.algorithm = match algorithm {
        "apollo" => GuidanceAlgorithm::Apollo,
        "fnpeg" => GuidanceAlgorithm::Fnpeg,
        other => panic!("no algorithm {other}"),
    };
    Arc::new(Scenario::build(cfg, &entrynav::files::no_files).unwrap())
}

fn print(report: &DeliveryReport) {
    for r in &report.rows {
        println!(
            "{:>12}: deployed {} failed {} mean miss {:?} rms {:?} median {:?} max {:?} mean dr {:?} cr {:?} ellipse {:?} max rate {:?} nav {:?}",
            r.name,
            r.deployed,
            r.failures,
            r.mean_miss_m,
            r.rms_miss_m,
            r.median_miss_m,
            r.max_miss_m,
            r.mean_downrange_m,
            r.mean_crossrange_m,
            r.ellipse_99,
            r.max_bank_rate_deg_s,
            r.rms_nav_position_error_m
        );
        if let Some(f) = &r.first_failure {
            println!("   first failure: run {} {}", f.0, f.1);
        }
    }
}

/// [`msl`] with small navigation errors: the filter's atmosphere is the truth's mean profile and
/// the truth atmosphere is not perturbed, so only the vehicle and entry-state dispersions remain
/// (C_D S/m and L/D are estimated as augmented states).
fn msl_small_nav_errors(algorithm: &str) -> Arc<Scenario> {
    let s = msl(algorithm);
    let mut cfg = s.config.clone();
    cfg.filter.atmosphere = cfg.truth.atmosphere.clone();
    cfg.truth.perturbation = None;
    let text = cfg.to_toml_string();
    let cfg = ScenarioConfig::from_toml_str(&text, "msl-guided small-nav test").unwrap();
    Arc::new(Scenario::build(cfg, &entrynav::files::no_files).unwrap())
}

/// The delivery tables of docs/guidance.md: 200 runs, seed 2800, both algorithms, `msl-airdata`
/// as shipped and with small navigation errors. Run with
/// `cargo test --release -p entrynav --test guided_loop delivery_tables -- --ignored --nocapture`.
#[test]
#[ignore]
fn delivery_tables_for_the_docs() {
    for small in [false, true] {
        for alg in ["apollo", "fnpeg"] {
            let s = if small {
                msl_small_nav_errors(alg)
            } else {
                msl(alg)
            };
            let r =
                run_delivery(&s, &[FilterKind::Ekf, FilterKind::Ukf], 200, 2800, &|_| {}).unwrap();
            println!("small nav errors {small}, {alg}, 200 runs, seed 2800");
            print(&r);
        }
    }
}

fn row<'a>(r: &'a DeliveryReport, name: &str) -> &'a entrynav::sim::guided::delivery::DeliveryRow {
    r.rows.iter().find(|x| x.name == name).unwrap()
}

#[test]
fn with_small_nav_errors_the_filter_in_the_loop_delivers_like_perfect_navigation() {
    let s = msl_small_nav_errors("fnpeg");
    let r = run_delivery(&s, &[FilterKind::Ekf], 20, 28, &|_| {}).unwrap();
    print(&r);
    let (perfect, ekf, unguided) = (row(&r, "perfect-nav"), row(&r, "ekf"), row(&r, "unguided"));
    // The premise: the EKF knows where it is to tens of metres at deployment.
    let nav = ekf.rms_nav_position_error_m.unwrap();
    assert!(nav < 100.0, "nav error {nav} m");
    assert!(ekf.deployed >= 12 && perfect.deployed >= 12);
    let (e, p) = (ekf.rms_miss_m.unwrap(), perfect.rms_miss_m.unwrap());
    assert!((e - p).abs() < 100.0, "EKF RMS miss {e} m vs perfect {p} m");
    assert!(e < 0.05 * unguided.rms_miss_m.unwrap());
    // Run by run, on the runs both deployed.
    for (run, rows) in r.per_run.iter().enumerate() {
        if let (Ok(p), Ok(e)) = (&rows[0], &rows[2]) {
            assert!(
                (p.miss_m - e.miss_m).abs() < 300.0,
                "run {run}: perfect {} m, EKF {} m",
                p.miss_m,
                e.miss_m
            );
        }
    }
}

#[test]
fn with_the_filter_in_the_loop_the_miss_follows_the_navigation_error() {
    // msl-airdata as shipped: the onboard exponential atmosphere is 21 % off the mean at 80 km and
    // the truth atmosphere is perturbed, so the IMU/airdata EKF drifts kilometres downrange. Guidance
    // steers the estimate onto the target, so the vehicle misses by about the navigation error.
    let s = msl("apollo");
    let r = run_delivery(&s, &[FilterKind::Ekf], 10, 28, &|_| {}).unwrap();
    print(&r);
    for (run, rows) in r.per_run.iter().enumerate() {
        if let Ok(e) = &rows[2] {
            let nav = e.nav_error.unwrap();
            assert!(
                (e.miss_m - nav.position_m).abs() < 0.5 * nav.position_m + 1000.0,
                "run {run}: miss {} m, nav error {} m",
                e.miss_m,
                nav.position_m
            );
        }
    }
    let ekf = row(&r, "ekf");
    assert!(ekf.rms_miss_m.unwrap() > 3.0 * row(&r, "perfect-nav").rms_miss_m.unwrap());
    assert!(ekf.rms_miss_m.unwrap() < 0.2 * row(&r, "unguided").rms_miss_m.unwrap());
}

#[test]
fn the_bank_rate_limit_holds_in_every_run_and_failures_are_counted() {
    for alg in ["apollo", "fnpeg"] {
        let s = msl(alg);
        let r = run_delivery(&s, &[FilterKind::Ekf, FilterKind::Ukf], 12, 7, &|_| {}).unwrap();
        let limit = r.bank_rate_limit_deg_s;
        for (run, rows) in r.per_run.iter().enumerate() {
            assert_eq!(rows.len(), 4);
            for d in rows.iter().flatten() {
                assert!(
                    d.max_bank_rate_deg_s <= limit * (1.0 + 1e-9),
                    "{alg} run {run}: {} deg/s",
                    d.max_bank_rate_deg_s
                );
            }
        }
        for x in &r.rows {
            assert!(x.rate_limit_held, "{alg} {}", x.name);
            assert_eq!(x.deployed + x.failures, 12, "{alg} {}", x.name);
            assert_eq!(x.failures > 0, x.first_failure.is_some());
        }
        // The limit binds: guidance reverses at the full rate.
        assert!(row(&r, "ekf").max_bank_rate_deg_s.unwrap() > 0.99 * limit);
    }
}

#[test]
fn delivery_is_reproducible_on_any_thread_count() {
    let s = msl("apollo");
    let on = |threads: usize| {
        rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap()
            .install(|| run_delivery(&s, &[FilterKind::Ekf], 8, 99, &|_| {}).unwrap())
    };
    let (one, two) = (on(1), on(2));
    assert_eq!(one, two);
    assert_eq!(one.per_run, two.per_run);
    assert_eq!(one, on(2), "a second study with the same seed");
}

#[test]
fn a_run_draws_the_truth_and_filter_start_as_the_engine_does_for_its_run_seed() {
    let s = msl("apollo");
    let (seed, run) = (28, 3);
    let mut a = EntryCoSim::for_run(Arc::clone(&s), FilterKind::Ekf, seed, run).unwrap();
    let mut b = EntryCoSim::new(
        Arc::clone(&s),
        FilterKind::Ekf,
        run_seed(seed, run as u64),
        true,
    )
    .unwrap();
    for k in 0..40 {
        let t = k as f64 * 0.25;
        a.do_step(t, 0.25, 0.5, &[]).unwrap();
        b.do_step(t, 0.25, 0.5, &[]).unwrap();
    }
    assert_eq!(a.truth().outputs(), b.truth().outputs());
    assert_eq!(a.nav().estimate(), b.nav().estimate());
}
