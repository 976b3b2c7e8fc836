//! The design studies refuse every out-of-range count, size and interval before any work, with a
//! message naming the option, the value and the range (an options fuzz found `beacons = 10^13`,
//! `starts`, `particles`, `orbiters`, `k`, `batch` aborting on a 10^15-byte allocation,
//! `time_limit = 1e300` panicking on a `Duration` overflow, `grid_deg = 1e-9` and
//! `iterations = 10^13` never ending).

use entrynav_studies::design::{GroundObjectiveName, GroundOptions, OrbiterOptions, SelectOptions};
use entrynav_studies::design::{SelectObjectiveName, run_ground_design, run_site_selection};
use entrynav_studies::progress::silent;
use entrynav_studies::{ErrorKind, ScenarioInput, StudyError};

const HUGE: usize = 10_000_000_000_000;

fn refused(r: Result<(), StudyError>) -> String {
    let e = r.expect_err("refused");
    assert_eq!(e.kind(), ErrorKind::Refused, "{e}");
    e.to_string()
}

#[test]
fn ground_counts_are_bounded_and_named() {
    let g = |f: fn(&mut GroundOptions)| {
        let mut o = GroundOptions::default();
        f(&mut o);
        refused(o.validate())
    };
    assert_eq!(
        g(|o| o.beacons = Some(HUGE)),
        "beacons = 10000000000000 is out of range: must be from 1 to 100"
    );
    assert_eq!(
        g(|o| o.starts = Some(HUGE)),
        "starts = 10000000000000 is out of range: must be from 1 to 1000"
    );
    assert_eq!(
        g(|o| o.particles = Some(HUGE)),
        "particles = 10000000000000 is out of range: must be from 2 to 10000"
    );
    assert_eq!(
        g(|o| o.iterations = Some(HUGE)),
        "iterations = 10000000000000 is out of range: must be from 0 to 1000000"
    );
    assert_eq!(
        g(|o| o.polish_iterations = Some(HUGE)),
        "polish_iterations = 10000000000000 is out of range: must be from 0 to 100000"
    );
    assert!(
        g(|o| {
            o.starts = Some(1000);
            o.particles = Some(10_000);
        })
        .starts_with("search budget (starts, particles, iterations, polish_iterations) = ")
    );
    assert_eq!(
        g(|o| o.check_runs = 5),
        "check_runs = 5 is out of range: must be from 10 to 100000"
    );
    assert_eq!(
        g(|o| o.threads = Some(HUGE)),
        "threads = 10000000000000 is out of range: must be from 1 to 1024"
    );
    // A skipped check does not care about its run count.
    let o = GroundOptions {
        check_runs: 5,
        no_check: true,
        ..GroundOptions::default()
    };
    assert!(o.validate().is_ok());
}

#[test]
fn orbiter_counts_are_bounded_and_named() {
    let o = OrbiterOptions {
        orbiters: Some(HUGE),
        ..OrbiterOptions::default()
    };
    assert_eq!(
        refused(o.validate()),
        "orbiters = 10000000000000 is out of range: must be from 1 to 100"
    );
    let o = OrbiterOptions {
        iterations: Some(HUGE),
        ..OrbiterOptions::default()
    };
    assert!(refused(o.validate()).starts_with("iterations = 10000000000000"));
    assert!(OrbiterOptions::default().validate().is_ok());
}

#[test]
fn selection_sizes_and_intervals_are_bounded_and_named() {
    let s = |f: fn(&mut SelectOptions)| {
        let mut o = SelectOptions::default();
        f(&mut o);
        refused(o.validate())
    };
    assert_eq!(
        s(|o| o.k = HUGE),
        "k = 10000000000000 is out of range: must be from 1 to 100"
    );
    assert_eq!(
        s(|o| o.batch = HUGE),
        "batch = 10000000000000 is out of range: must be from 1 to 1024"
    );
    assert_eq!(
        s(|o| o.time_limit = Some(1e300)),
        "time_limit = 1e300 is out of range: must be a number from 0 to 1000000"
    );
    assert_eq!(
        s(|o| o.grid_deg = 1e-9),
        "grid_deg = 1e-9 is out of range: must be a number from 0.05 to 30"
    );
    assert!(s(|o| o.gap = f64::NAN).starts_with("gap = NaN is out of range"));
    assert!(s(|o| o.brute_force_limit = HUGE).starts_with("brute_force_limit = 10000000000000"));
    assert_eq!(
        s(|o| o.region = Some(vec![1.0, 0.0, 0.0, 1.0])),
        "region = 1 0 0 1 is out of range: must be LAT_MIN <= LAT_MAX in [-90, 90] and LON_MIN <= LON_MAX in [-360, 360] [deg]"
    );
    assert_eq!(
        s(|o| o.eig_epochs = Some(10.0)),
        "eig_epochs applies to criterion min-eig only"
    );
    assert!(
        s(|o| {
            o.objective = Some(SelectObjectiveName::Nav);
            o.exact = true;
        })
        .starts_with("exact certifies the convex criteria")
    );
    assert!(SelectOptions::default().validate().is_ok());
}

#[test]
fn a_study_refuses_before_it_loads_anything() {
    // The scenario is never built: the options are refused first.
    let input = ScenarioInput::resolve("ground-beacons-3", &[]).unwrap();
    let o = GroundOptions {
        beacons: Some(HUGE),
        objective: GroundObjectiveName::MinDelta,
        ..GroundOptions::default()
    };
    let e = run_ground_design(&input, &o, &silent).unwrap_err();
    assert!(e.to_string().starts_with("beacons = "), "{e}");
    let o = SelectOptions {
        grid_deg: 1e-9,
        ..SelectOptions::default()
    };
    let e = run_site_selection(&input, &o, &silent).unwrap_err();
    assert!(e.to_string().starts_with("grid_deg = "), "{e}");
}

#[test]
fn options_deserialise_from_the_front_ends_names() {
    let o: GroundOptions =
        serde_json::from_str(r#"{"beacons": 3, "objective": "pcrlb", "method": "linear"}"#)
            .unwrap();
    assert_eq!(o.objective, GroundObjectiveName::PcrlbFinal);
    assert_eq!(o.beacons, Some(3));
    let e = serde_json::from_str::<SelectOptions>(r#"{"kk": 3}"#).unwrap_err();
    assert!(e.to_string().contains("unknown field `kk`"), "{e}");
}
