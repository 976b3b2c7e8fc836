//! The nominal-trajectory position bound for beacon design (`sim::bounds::nominal_bound`) against the
//! trade's own PCRLB machinery run on the same nominal truth, and its basic properties.

use entrynav::beacons::Beacon;
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav::sim::bounds::pcrlb::bound_run;
use entrynav::sim::bounds::pcrlb_sums::BoundSums;
use entrynav::sim::bounds::{NominalBound, NominalBoundError, RangeSite};
use entrynav::sim::monte_carlo::state_names;
use entrynav::sim::{RecordedRun, simulate_truth};
use rand::SeedableRng;

fn scenario(name: &str) -> Scenario {
    Scenario::build(
        ScenarioConfig::builtin(name).unwrap(),
        &entrynav::files::no_files,
    )
    .unwrap()
}

/// The scenario's own surface beacons as range sites.
fn own_sites(s: &Scenario, sigma: f64) -> Vec<RangeSite> {
    s.beacons
        .iter()
        .map(|b| match b {
            Beacon::Surface(b) => RangeSite {
                position_m: b.position_at(0.0),
                sigma_m: sigma,
                elevation_mask_rad: 0.0,
            },
            Beacon::Orbiter(_) => panic!("not a surface beacon"),
        })
        .collect()
}

#[test]
fn equals_the_trade_recursion_on_the_nominal_truth() {
    // The trade's bound (bound_run + BoundSums + pcrlb_recursion) on one run, the nominal truth:
    // the same quantity computed by another algebra (information form with Cholesky on the
    // correlation scale, against sequential rank-one covariance updates).
    let s = scenario("ground-beacons-3");
    let draw = s.nominal_truth();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
    let truth = simulate_truth(&s, &draw, &mut rng).unwrap();
    let rec = RecordedRun {
        run: 0,
        draw,
        truth,
        x0: Vec::new(),
    };
    let mut sums = BoundSums::new(&s);
    sums.add_runs(&[bound_run(&s, &rec)]);
    let trade = sums.report(&state_names(&s));
    assert!(trade.available, "{:?}", trade.reason);
    let want = &trade.series["pos_m"];

    let nominal = NominalBound::new(&s).unwrap();
    let got = nominal.ground_sites(&own_sites(&s, 100.0)).unwrap();
    assert_eq!(got.times_s, trade.times_s);
    assert_eq!(got.pos_m.len(), want.len());
    for (k, (a, b)) in got.pos_m.iter().zip(want).enumerate() {
        assert!((a - b).abs() <= 1e-6 * b, "epoch {k}: {a} vs {b}");
    }
    // The bound falls from the prior (1 km radius and 0.2 deg in angle) to tens of metres.
    assert!(got.pos_m[0] > 500.0 && got.final_value() < 100.0, "{got:?}");
}

#[test]
fn a_further_beacon_never_loosens_the_bound_and_none_leaves_the_prior_propagated() {
    let s = scenario("ground-beacons-3");
    let nominal = NominalBound::new(&s).unwrap();
    let sites = own_sites(&s, 100.0);
    let two = nominal.ground_sites(&sites[..2]).unwrap();
    let three = nominal.ground_sites(&sites).unwrap();
    for (a, b) in three.pos_m.iter().zip(&two.pos_m) {
        assert!(*a <= b * (1.0 + 1e-9), "{a} > {b}");
    }
    assert!(three.time_avg() < two.time_avg());
    let none = nominal.ground_sites(&[]).unwrap();
    assert!(none.final_value() > 10.0 * three.final_value());
    // A noisier beacon set is worse.
    let noisy = nominal.ground_sites(&own_sites(&s, 300.0)).unwrap();
    assert!(noisy.time_avg() > three.time_avg());
}

#[test]
fn refuses_bad_sites_and_scenarios_without_ranges() {
    let s = scenario("ground-beacons-3");
    let nominal = NominalBound::new(&s).unwrap();
    let mut sites = own_sites(&s, 100.0);
    sites[1].sigma_m = 0.0;
    assert!(matches!(
        nominal.ground_sites(&sites),
        Err(NominalBoundError::BadSite { index: 1, .. })
    ));
    sites[1].sigma_m = 100.0;
    sites[2].position_m[0] = f64::NAN;
    assert!(matches!(
        nominal.ground_sites(&sites),
        Err(NominalBoundError::BadSite { index: 2, .. })
    ));
    let err = NominalBound::new(&scenario("msl-airdata")).unwrap_err();
    assert!(matches!(err, NominalBoundError::NoRange(_)), "{err}");
}

#[test]
fn an_elevation_mask_removes_the_low_measurements_as_the_engine_does() {
    // The trade's recursion on the nominal truth of the scenario with a 10 deg mask on every
    // beacon (the engine drops the masked measurements) equals the nominal bound with masked sites.
    let mut cfg = ScenarioConfig::builtin("ground-beacons-3").unwrap();
    for b in &mut cfg.beacons {
        if let entrynav::beacons::BeaconConfig::Surface(c) = b {
            c.elevation_mask_deg = Some(10.0);
        }
    }
    let s = Scenario::build(cfg, &entrynav::files::no_files).unwrap();
    let draw = s.nominal_truth();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
    let truth = simulate_truth(&s, &draw, &mut rng).unwrap();
    let measured = truth
        .epochs
        .iter()
        .filter(|e| e.values.iter().any(Option::is_some))
        .count();
    assert!(
        measured < truth.epochs.len(),
        "the mask removed no measurement"
    );
    let rec = RecordedRun {
        run: 0,
        draw,
        truth,
        x0: Vec::new(),
    };
    let mut sums = BoundSums::new(&s);
    sums.add_runs(&[bound_run(&s, &rec)]);
    let trade = sums.report(&state_names(&s));
    let nominal = NominalBound::new(&s).unwrap();
    let mut sites = own_sites(&s, 100.0);
    for site in &mut sites {
        site.elevation_mask_rad = 10f64.to_radians();
    }
    let got = nominal.ground_sites(&sites).unwrap();
    let want = &trade.series["pos_m"];
    // The trade's epochs are those with a measurement; compare at those times.
    for (t, b) in trade.times_s.iter().zip(want) {
        let k = got.times_s.iter().position(|x| x == t).unwrap();
        assert!(
            (got.pos_m[k] - b).abs() <= 1e-6 * b,
            "t = {t}: {} vs {b}",
            got.pos_m[k]
        );
    }
    let unmasked = nominal.ground_sites(&own_sites(&s, 100.0)).unwrap();
    assert!(got.time_avg() > unmasked.time_avg());
}

#[test]
fn an_elevation_mask_outside_0_to_90_deg_is_refused_naming_the_field() {
    for bad in [-1.0, 90.0, f64::NAN] {
        let mut cfg = ScenarioConfig::builtin("ground-beacons-3").unwrap();
        if let entrynav::beacons::BeaconConfig::Surface(c) = &mut cfg.beacons[1] {
            c.elevation_mask_deg = Some(bad);
        }
        let err = Scenario::build(cfg, &entrynav::files::no_files)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("beacons[1].elevation_mask_deg") && err.contains("[0, 90)"),
            "{bad}: {err}"
        );
    }
}

#[test]
fn moving_sites_equal_the_trade_recursion_for_the_orbiters() {
    // orbiters-3: the scenario's three orbiters as moving sites, against the trade's recursion
    // on the nominal truth (line of sight by eq. 58-60 in both).
    let s = scenario("orbiters-3");
    let draw = s.nominal_truth();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(9);
    let truth = simulate_truth(&s, &draw, &mut rng).unwrap();
    let rec = RecordedRun {
        run: 0,
        draw,
        truth,
        x0: Vec::new(),
    };
    let mut sums = BoundSums::new(&s);
    sums.add_runs(&[bound_run(&s, &rec)]);
    let trade = sums.report(&state_names(&s));
    let nominal = NominalBound::new(&s).unwrap();
    let times = nominal.epoch_times();
    let positions: Vec<Vec<[f64; 3]>> = s
        .beacons
        .iter()
        .map(|b| times.iter().map(|t| b.position_at(*t)).collect())
        .collect();
    let sigma: Vec<f64> = s
        .config
        .beacons
        .iter()
        .map(|b| b.range_sigma_m().unwrap())
        .collect();
    let got = nominal.moving_sites(&sigma, &positions).unwrap();
    let want = &trade.series["pos_m"];
    for (t, b) in trade.times_s.iter().zip(want) {
        let k = got.times_s.iter().position(|x| x == t).unwrap();
        assert!(
            (got.pos_m[k] - b).abs() <= 1e-6 * b,
            "t = {t}: {} vs {b}",
            got.pos_m[k]
        );
    }
    // A wrong number of positions is refused.
    assert!(nominal.moving_sites(&sigma, &positions[..2]).is_err());
}
