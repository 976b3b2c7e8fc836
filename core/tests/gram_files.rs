//! Mars-GRAM output files as they come: `#` header line, stacked Monte Carlo profiles, the
//! radius datum, explicit columns, bad files, and the per-run profile of a truth profile set.

use entrynav::Planet;
use entrynav::atmosphere::{
    Atmosphere, AtmosphereConfig, AtmosphereError, Datum, HeightReference, MAX_PROFILES, Placement,
    ProfileChoice, TableColumns, TableFormat, areoid_radius_m, parse_mars_gram, parse_profiles,
};
use entrynav::scenario::{Scenario, ScenarioConfig};
use rand::SeedableRng;

const MC2: &str = include_str!("data/gram/montecarlo-2.txt");
const MC3: &str = include_str!("data/gram/montecarlo-3.txt");
const AVERAGED: &str = include_str!("data/gram/averaged.txt");
const HGTMOLA: &str = include_str!("data/gram/hgtmola.txt");
const R_SPHERE: f64 = 3_396_200.0;
const LAT: f64 = -3.919;

/// DENSTOT of profile `k` at `h_km`, the formula the fixtures were written from (README).
fn fixture_density(k: usize, h_km: f64) -> f64 {
    2.032e-2
        * (-(h_km + 5.0) / 9.0).exp()
        * (1.0 + 0.15 * (h_km / 15.0 + 2.0 * k as f64).sin())
        * (1.0 + 0.12 * k as f64)
}

fn placement(datum: Option<Datum>) -> Placement {
    Placement {
        datum,
        sphere_radius_m: R_SPHERE,
        latitude_rad: LAT.to_radians(),
    }
}

fn read(
    text: &str,
    datum: Option<Datum>,
) -> Result<entrynav::atmosphere::ProfileSet, AtmosphereError> {
    let fmt = TableFormat::detect(text);
    parse_profiles(
        text,
        "f.txt",
        fmt,
        &TableColumns::default(),
        &placement(datum),
    )
}

#[test]
fn monte_carlo_file_splits_into_profiles_placed_by_radius() {
    assert_eq!(TableFormat::detect(MC2), TableFormat::MarsGram);
    let set = read(MC2, None).unwrap();
    assert_eq!(set.profiles.len(), 2);
    assert_eq!(
        (set.height_column.as_str(), set.density_column.as_str()),
        ("Var_X", "DENSTOT")
    );
    assert_eq!(set.reference, HeightReference::Radius("Radius".into()));
    assert!(set.assumption_warning().is_none());
    assert_eq!(
        (set.profiles[0].first_line, set.profiles[0].last_line),
        (2, 33)
    );
    assert_eq!(
        (set.profiles[1].first_line, set.profiles[1].last_line),
        (34, 65)
    );
    // Radius column = areoid(LAT) + Var_X, so the sphere altitude of Var_X = h is
    // h + areoid − sphere (rounded to the file's metre digits).
    let shift = areoid_radius_m(LAT.to_radians()) - R_SPHERE;
    for (k, p) in set.profiles.iter().enumerate() {
        assert_eq!(p.table.num_knots(), 32);
        let (lo, hi) = p.table.altitude_range();
        assert!(
            (lo - (-5e3 + shift)).abs() < 1.0 && (hi - (150e3 + shift)).abs() < 1.0,
            "{lo} {hi}"
        );
        for h_km in [0.0, 40.0, 125.0] {
            let rho = p.table.density(h_km * 1e3 + shift);
            assert!(
                (rho / fixture_density(k, h_km) - 1.0).abs() < 2e-3,
                "profile {k} at {h_km} km: {rho}"
            );
        }
    }
    let three = read(MC3, None).unwrap();
    assert_eq!(three.profiles.len(), 3);
    assert_ne!(three.profiles[1], three.profiles[2]);
}

#[test]
fn averaged_file_and_single_profile_reader() {
    let set = read(AVERAGED, None).unwrap();
    assert_eq!(set.profiles.len(), 1);
    assert_eq!(set.profiles[0].first_line, 2);
    // The single-profile reader takes the averaged file, heights as given.
    let t = parse_mars_gram(AVERAGED, "avg.txt", &TableColumns::default()).unwrap();
    assert_eq!(t.altitude_range(), (-5e3, 150e3));
    // ... and refuses a Monte Carlo set, naming the lines where the second profile starts.
    let e = parse_mars_gram(MC2, "mc.txt", &TableColumns::default()).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("mc.txt: lines 33 and 34") && msg.contains("profile set"),
        "{msg}"
    );
}

#[test]
fn datum_of_a_file_without_radius() {
    let assumed = read(HGTMOLA, None).unwrap();
    assert_eq!(assumed.height_column, "HgtMOLA");
    assert_eq!(assumed.reference, HeightReference::Sphere { assumed: true });
    let w = assumed.assumption_warning().unwrap();
    assert!(
        w.contains("f.txt") && w.contains("HgtMOLA") && w.contains("areoid"),
        "{w}"
    );
    let sphere = read(HGTMOLA, Some(Datum::Sphere)).unwrap();
    assert!(sphere.assumption_warning().is_none());
    assert_eq!(sphere.profiles[0].table.altitude_range(), (-5e3, 150e3));
    let areoid = read(HGTMOLA, Some(Datum::Areoid)).unwrap();
    let shift = areoid_radius_m(LAT.to_radians()) - R_SPHERE;
    let (lo, _) = areoid.profiles[0].table.altitude_range();
    assert!((lo - (-5e3 + shift)).abs() < 1e-6, "{lo}");
    // An explicit datum overrides the radius column.
    let mc = read(MC2, Some(Datum::Sphere)).unwrap();
    assert_eq!(mc.profiles[0].table.altitude_range(), (-5e3, 150e3));
}

#[test]
fn areoid_approximation_matches_the_gram_radii() {
    assert!((areoid_radius_m(0.0) - 3395.5e3).abs() < 1.0);
    assert!((areoid_radius_m(80f64.to_radians()) - 3378.7e3).abs() < 10.0);
    assert_eq!(areoid_radius_m(0.3), areoid_radius_m(-0.3));
}

#[test]
fn explicit_columns_override_the_defaults() {
    let cols = TableColumns {
        density: "DENSHI".into(),
        ..TableColumns::default()
    };
    let set = parse_profiles(MC2, "f.txt", TableFormat::MarsGram, &cols, &placement(None)).unwrap();
    let base = read(MC2, None).unwrap();
    // Knot 5 is Var_X = 20 km: DENSHI = 1.15 DENSAV, DENSTOT = DENSAV (1 + 0.15 sin(20/15)).
    let h = base.profiles[0].table.altitudes_m()[5];
    let ratio = set.profiles[0].table.density(h) / base.profiles[0].table.density(h);
    let want = 1.15 / (1.0 + 0.15 * (20.0f64 / 15.0).sin());
    assert!((ratio / want - 1.0).abs() < 2e-3, "{ratio} vs {want}");
    assert_eq!(set.density_column, "DENSHI");
    let cols = TableColumns {
        height: "Altitude".into(),
        ..TableColumns::default()
    };
    let e =
        parse_profiles(MC2, "f.txt", TableFormat::MarsGram, &cols, &placement(None)).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("f.txt: line 1: no height column named 'Altitude'") && msg.contains("Var_X"),
        "{msg}"
    );
}

#[test]
fn bad_files_name_file_line_and_problem() {
    let mut lines: Vec<&str> = MC2.lines().collect();
    lines[40] = "   30.0000  1.727E-02  2.032E-02  2.337E-02  abc  0.300 3390.419 3.7210 1.520     0    0.000        0       0   0.000";
    let e = read(&lines.join("\n"), None).unwrap_err();
    assert!(
        e.to_string()
            .contains("f.txt: line 41: column DENSTOT: 'abc' is not a number"),
        "{e}"
    );
    // A stacked profile of two rows.
    let short = "#  Var_X DENSTOT\n1 1e-3\n2 5e-4\n3 1e-4\n1 1e-3\n2 5e-4\n";
    let e = read(short, None).unwrap_err();
    assert!(
        matches!(
            e,
            AtmosphereError::BadProfile {
                profile: 1,
                first_line: 5,
                last_line: 6,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(
        e.to_string()
            .contains("lines 5-6: profile 1: found 2 data rows"),
        "{e}"
    );
    // A small step back is a bad row, not a new profile.
    let e = read(
        "#  Var_X DENSTOT\n1 1e-3\n2 5e-4\n3 1e-4\n2.9 9e-5\n4 8e-5\n",
        None,
    )
    .unwrap_err();
    assert!(
        e.to_string()
            .contains("f.txt: lines 4 and 5: altitude 2.9 after 3 breaks the increasing order"),
        "{e}"
    );
    // A repeated height inside a profile.
    let e = read("#  Var_X DENSTOT\n1 1e-3\n2 5e-4\n2 1e-4\n", None).unwrap_err();
    assert!(
        e.to_string().contains("lines 3 and 4") && e.to_string().contains("repeats"),
        "{e}"
    );
    // Too many profiles.
    let mut many = String::from("#  Var_X DENSTOT\n");
    for _ in 0..=MAX_PROFILES {
        many.push_str("1 1e-3\n2 5e-4\n3 1e-4\n");
    }
    let e = read(&many, None).unwrap_err();
    assert!(
        matches!(
            e,
            AtmosphereError::TooManyProfiles {
                limit: MAX_PROFILES,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(
        e.to_string()
            .contains(&format!("line {}", 2 + 3 * MAX_PROFILES)),
        "{e}"
    );
    // Header names only, no data.
    let e = read("#  Var_X DENSTOT\n", None).unwrap_err();
    assert!(matches!(e, AtmosphereError::NoHeader { .. }), "{e:?}");
}

#[test]
fn profile_choice_cycles_or_selects() {
    let set = read(MC3, None).unwrap();
    let c = ProfileChoice::new(set.clone(), None).unwrap();
    assert!(c.is_cycling());
    let picked: Vec<usize> = (0..7).map(|r| c.profile_for_run(r)).collect();
    assert_eq!(picked, [0, 1, 2, 0, 1, 2, 0]);
    assert_eq!(c.provenance().rule, "run k flies profile k mod 3");
    let one = ProfileChoice::new(set.clone(), Some(2)).unwrap();
    assert!(!one.is_cycling() && one.profile_for_run(4) == 2);
    let e = ProfileChoice::new(set, Some(3)).unwrap_err();
    assert!(
        e.to_string()
            .contains("profile 3 does not exist: the file holds 3 profile(s), allowed 0 to 2"),
        "{e}"
    );
}

#[test]
fn scenario_table_fields_and_per_run_profiles() {
    let text = entrynav::scenario::builtin_toml("msl-airdata").unwrap();
    let mut cfg = ScenarioConfig::from_toml_str(text, "msl-airdata").unwrap();
    cfg.truth.atmosphere = toml::from_str(
        "model = 'table'\nfile = 'mc.txt'\nformat = 'mars-gram'\nheight_column = 'Var_X'\ndensity_column = 'DENSTOT'",
    )
    .unwrap();
    cfg.truth.perturbation = None;
    let load = |_: &str| Ok(MC2.to_string());
    let sc = Scenario::build(cfg.clone(), &load).unwrap();
    let choice = sc.truth_profiles.as_ref().unwrap();
    assert_eq!(choice.count(), 2);
    let h = 60e3;
    let want: Vec<f64> = choice
        .set
        .profiles
        .iter()
        .map(|p| p.table.density(h))
        .collect();
    assert_ne!(want[0], want[1]);
    for run in 0..4 {
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(run as u64);
        let d = sc.draw_truth_run(run, &mut rng);
        assert_eq!(d.model.atmosphere.density(h), want[run % 2], "run {run}");
    }
    // `profile = 1` flies profile 1 in every run; out of range is refused at build time.
    let mut one = cfg.clone();
    one.truth.atmosphere = toml::from_str(
        "model = 'table'\nfile = 'mc.txt'\nformat = 'mars-gram'\nprofile = 1\ndatum = 'areoid'",
    )
    .unwrap();
    let sc1 = Scenario::build(one.clone(), &load).unwrap();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(0);
    let d = sc1.draw_truth_run(0, &mut rng);
    let p1 = &sc1.truth_profiles.as_ref().unwrap().set.profiles[1];
    assert_eq!(d.model.atmosphere.density(h), p1.table.density(h));
    assert!(matches!(
        sc1.truth_profiles.as_ref().unwrap().set.reference,
        HeightReference::Areoid { .. }
    ));
    one.truth.atmosphere =
        toml::from_str("model = 'table'\nfile = 'mc.txt'\nformat = 'mars-gram'\nprofile = 2")
            .unwrap();
    let e = Scenario::build(one, &load).unwrap_err().to_string();
    assert!(
        e.contains("profile 2 does not exist") && e.contains("allowed 0 to 1"),
        "{e}"
    );
    // The single-profile build gives profile 0.
    let m = cfg.truth.atmosphere.build(&Planet::MARS, &load).unwrap();
    assert_eq!(m.density(h), want[0]);
    let _: AtmosphereConfig = cfg.truth.atmosphere;
}

/// The Monte Carlo path (`record_run`, used by every shard) picks the profile from the run index
/// alone: the same run gives the same profile whatever was recorded before it.
#[test]
fn recorded_runs_fly_profile_run_mod_n_in_any_order() {
    let text = entrynav::scenario::builtin_toml("msl-airdata").unwrap();
    let mut cfg = ScenarioConfig::from_toml_str(text, "msl-airdata").unwrap();
    cfg.truth.atmosphere =
        toml::from_str("model = 'table'\nfile = 'mc.txt'\nformat = 'mars-gram'").unwrap();
    cfg.truth.perturbation = None;
    let load = |_: &str| Ok(MC3.to_string());
    let sc = Scenario::build(cfg, &load).unwrap();
    let profiles = &sc.truth_profiles.as_ref().unwrap().set.profiles;
    let h = 70e3;
    let rho = |run: usize| {
        entrynav::sim::record_run(&sc, 11, run)
            .unwrap()
            .draw
            .model
            .atmosphere
            .density(h)
    };
    let late_first = [rho(5), rho(4)];
    let early_first = [rho(4), rho(5)];
    assert_eq!(late_first, [early_first[1], early_first[0]]);
    assert_eq!(early_first[0], profiles[1].table.density(h));
    assert_eq!(early_first[1], profiles[2].table.density(h));
}
