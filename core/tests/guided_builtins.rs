//! The guided built-ins of issue 28 against its acceptance: `four-beacon-fusion-guided` with the
//! EKF in the loop misses by at most twice what perfect navigation misses, with the bank rate
//! limit held in every run; `msl-guided` is flown by the guidance its `[guidance]` names and every
//! filter it lists can fly in the loop, deploys inside the box (issue 50) and gains from heading
//! alignment. (The no-dispersion misses and the delivery statistics on `msl-guided`'s guidance
//! settings from before issue 50 are checked in `core/tests/guidance.rs` and
//! `core/tests/guided_loop.rs`.)

use entrynav::estimation::nav::FilterKind;
use entrynav::guidance::{GuidanceAlgorithm, Trigger};
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav::sim::guided::delivery::{DeliveryRow, run_delivery};

fn builtin(name: &str) -> Scenario {
    Scenario::build(
        ScenarioConfig::builtin(name).unwrap(),
        &entrynav::files::no_files,
    )
    .unwrap()
}

fn row<'a>(rows: &'a [DeliveryRow], name: &str) -> &'a DeliveryRow {
    rows.iter().find(|r| r.name == name).unwrap()
}

#[test]
fn four_beacon_fusion_guided_ekf_misses_within_twice_perfect_navigation() {
    let sc = builtin("four-beacon-fusion-guided");
    let g = sc.config.guidance.as_ref().unwrap();
    assert_eq!(g.algorithm, GuidanceAlgorithm::Fnpeg);
    let report =
        run_delivery(&sc, &[FilterKind::Ekf, FilterKind::Dcifaif], 10, 1, &|_| ()).unwrap();
    let perfect = row(&report.rows, "perfect-nav");
    let unguided = row(&report.rows, "unguided");
    for name in ["ekf", "dcifaif"] {
        let r = row(&report.rows, name);
        assert_eq!(r.failures, 0, "{name}: {:?}", r.first_failure);
        assert!(r.rate_limit_held, "{name}");
        let (miss, best) = (r.rms_miss_m.unwrap(), perfect.rms_miss_m.unwrap());
        let nav = r.rms_nav_position_error_m.unwrap();
        println!(
            "{name}: RMS miss {miss:.1} m (perfect navigation {best:.1} m), nav error {nav:.1} m"
        );
        assert!(
            miss <= 2.0 * best,
            "{name}: miss {miss} m vs perfect navigation {best} m"
        );
        // The filter's error at deployment is that of a consistent filter on this entry (a few
        // metres), not the hundred metres a stale bank history gave.
        assert!(nav < 20.0, "{name}: navigation error {nav} m at deployment");
        assert!(miss * 100.0 < unguided.rms_miss_m.unwrap());
    }
}

#[test]
fn msl_guided_flies_apollo_and_every_filter_it_lists_flies_in_the_loop() {
    let sc = builtin("msl-guided");
    let g = sc.config.guidance.as_ref().unwrap();
    assert_eq!(g.algorithm, GuidanceAlgorithm::Apollo);
    assert_eq!(sc.truth_bank, g.reference_bank_deg.to_radians());
    let filters: Vec<FilterKind> = FilterKind::ALL
        .into_iter()
        .filter(|k| k.misfit(&sc.onboard).is_none())
        .collect();
    assert!(filters.contains(&FilterKind::Ekf), "{filters:?}");
    let report = run_delivery(&sc, &filters, 2, 3, &|_| ()).unwrap();
    for r in &report.rows {
        println!(
            "{}: deployed {} failed {} RMS miss {:?} nav {:?}",
            r.name, r.deployed, r.failures, r.rms_miss_m, r.rms_nav_position_error_m
        );
        assert!(r.rate_limit_held, "{}", r.name);
        assert_eq!(r.deployed + r.failures, 2, "{}", r.name);
    }
}

/// Issue 50's acceptance with perfect navigation, as `guidance deliver --scenario msl-guided
/// --runs 1000 --seed 3 --filters none` flies it: with its defaults (range trigger, 7 km altitude
/// safeguard, MSL-class aerodynamic dispersions) at least 999 of 1000 runs deploy inside the box
/// (altitude ≥ 5 km), with a 99 % ellipse of at most 7.7 × 6.6 km full axes; with the speed
/// trigger selected, the same count and at most 20 × 7 km.
#[test]
fn msl_guided_deploys_inside_the_box_in_999_of_1000_runs_with_either_trigger() {
    let range = builtin("msl-guided");
    let g = range.config.guidance.as_ref().unwrap();
    assert!(matches!(g.trigger, Trigger::Range(_)), "{:?}", g.trigger);
    let mut cfg = range.config.clone();
    cfg.guidance.as_mut().unwrap().trigger = Trigger::SpeedMps(450.0);
    let speed = Scenario::build(cfg, &entrynav::files::no_files).unwrap();
    for (sc, full_axes_m) in [(&range, [7700.0, 6600.0]), (&speed, [20000.0, 7000.0])] {
        let report = run_delivery(sc, &[], 1000, 3, &|_| ()).unwrap();
        let r = row(&report.rows, "perfect-nav");
        let e = r.ellipse_99.as_ref().unwrap();
        println!(
            "{:?}: deployed {} failed {} inside the box {} ({:?}) ellipse {:.0} x {:.0} m full",
            sc.config.guidance.as_ref().unwrap().trigger,
            r.deployed,
            r.failures,
            r.inside_box,
            r.outside_box_by_limit,
            2.0 * e.semi_major_m,
            2.0 * e.semi_minor_m
        );
        assert!(r.inside_box >= 999, "{:?}", r.outside_box_by_limit);
        assert!(2.0 * e.semi_major_m <= full_axes_m[0], "{e:?}");
        assert!(2.0 * e.semi_minor_m <= full_axes_m[1], "{e:?}");
    }
}

/// Apollo's heading alignment (`guidance.apollo.heading_alignment_speed_mps`, msl-guided's
/// default at 1100 m/s): on msl-guided with perfect navigation (200 runs, seed 3) it steers the
/// velocity onto the target and flies near lift-up, so against the same entry without it the
/// crossrange miss collapses, every run deploys higher than the lowest run without it, and the
/// median run deploys near 10 km, the altitude margin issue 50 asks of the nominal (1000 runs:
/// RMS miss 43 → 1.5 m, lowest deployment 6.2 → 8.6 km, median 8.4 → 10.4 km; docs/guidance.md).
#[test]
fn heading_alignment_nulls_the_crossrange_and_deploys_near_10_km() {
    let aligned = builtin("msl-guided");
    let mut cfg = aligned.config.clone();
    let apollo = &mut cfg.guidance.as_mut().unwrap().apollo;
    assert_eq!(apollo.heading_alignment_speed_mps, Some(1100.0));
    apollo.heading_alignment_speed_mps = None;
    let hold = Scenario::build(cfg, &entrynav::files::no_files).unwrap();
    let fly = |sc: &Scenario| {
        let report = run_delivery(sc, &[], 200, 3, &|_| ()).unwrap();
        let r = row(&report.rows, "perfect-nav").clone();
        let mut altitudes: Vec<f64> = report
            .per_run
            .iter()
            .filter_map(|rows| rows[0].as_ref().ok())
            .map(|d| d.altitude_m)
            .collect();
        altitudes.sort_by(f64::total_cmp);
        (r, altitudes[0], altitudes[altitudes.len() / 2])
    };
    let ((before, low_before, med_before), (after, low_after, med_after)) =
        (fly(&hold), fly(&aligned));
    let (m0, m1) = (before.rms_miss_m.unwrap(), after.rms_miss_m.unwrap());
    println!(
        "RMS miss {m0:.1} -> {m1:.1} m, deployment lowest {low_before:.0} -> {low_after:.0} m, median {med_before:.0} -> {med_after:.0} m"
    );
    assert_eq!((before.inside_box, after.inside_box), (200, 200));
    assert!(m1 < 0.2 * m0, "RMS miss {m0} -> {m1} m");
    assert!(
        low_after > low_before + 1000.0,
        "{low_before} -> {low_after} m"
    );
    assert!(
        (9500.0..11500.0).contains(&med_after),
        "median {med_after} m"
    );
    assert!(
        med_after > med_before + 1000.0,
        "median {med_before} -> {med_after} m"
    );
}

/// FNPEG with the recommended filter in the loop (issue 50: "FNPEG meets the same deployment
/// count"): every run deploys inside the box. FNPEG often reaches the target early and waits for
/// the pressure window, so it deploys at the window's edge; there the onboard dynamic pressure is
/// read with USKF-NN's C_D S/m estimate, not the dispersed onboard constant (which put 84 of 1000
/// runs above 850 Pa), and the window keeps 1 % inside the box (without it, 3 of 1000 at 850.1 Pa).
/// 100 runs, seed 3 (1000 runs: docs/guidance.md).
#[test]
fn fnpeg_with_uskf_nn_in_the_loop_deploys_inside_the_box() {
    let mut cfg = builtin("msl-guided").config;
    cfg.guidance.as_mut().unwrap().algorithm = GuidanceAlgorithm::Fnpeg;
    let sc = Scenario::build(cfg, &entrynav::files::no_files).unwrap();
    let report = run_delivery(&sc, &[FilterKind::UskfNn], 100, 3, &|_| ()).unwrap();
    let r = row(&report.rows, "uskf-nn");
    println!(
        "deployed {} inside the box {} ({:?})",
        r.deployed, r.inside_box, r.outside_box_by_limit
    );
    assert_eq!(
        (r.deployed, r.inside_box),
        (100, 100),
        "{:?}",
        r.outside_box_by_limit
    );
}
