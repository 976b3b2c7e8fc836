//! Behaviour tests of the atmosphere module: closed forms, fits, spline, parsers, perturbation
//! statistics and scenario configuration.

use entrynav::Planet;
use entrynav::atmosphere::{
    Atmosphere, AtmosphereConfig, AtmosphereError, AtmosphereModel, Cospar, Envelope, Exponential,
    HeightUnit, PerturbationConfig, PerturbationSpec, Perturbed, TableColumns, Tabulated,
    mars_mean_profile, parse_csv, parse_mars_gram,
};
use num_dual::first_derivative;
use proptest::prelude::*;

const R_MARS: f64 = 3_396_200.0;

fn rel(a: f64, b: f64) -> f64 {
    (a / b - 1.0).abs()
}

/// d density/dh by forward-mode AD.
fn ad_slope<A: Atmosphere>(m: &A, h: f64) -> f64 {
    first_derivative(|x| m.density(x), h).1
}

/// Central finite difference with step `dh`.
fn fd_slope<A: Atmosphere>(m: &A, h: f64, dh: f64) -> f64 {
    (m.density(h + dh) - m.density(h - dh)) / (2.0 * dh)
}

// ---------------------------------------------------------------- exponential / COSPAR

#[test]
fn exponential_equals_closed_form() {
    let e = Exponential::new(3e-4, 20e3, 9e3).unwrap();
    for h in [-2e3_f64, 0.0, 20e3, 57.3e3, 140e3] {
        let closed = 3e-4 * (-(h - 20e3) / 9e3).exp();
        assert!(rel(e.density(h), closed) < 1e-14, "h = {h}");
    }
}

#[test]
fn papers_reference_radius_form_gives_2e4_at_41_km() {
    let e = Exponential::from_reference_radius(2e-4, 3_437_200.0, 7_500.0, R_MARS).unwrap();
    assert!((e.h_ref - 41_000.0).abs() < 1e-9);
    assert!(rel(e.density(41_000.0_f64), 2e-4) < 1e-14);
    // seed 000 eq. 3: ρ0·exp((r0 − r)/hs) at r = R + 60 km.
    let r = R_MARS + 60e3;
    assert!(
        rel(
            e.density(60e3_f64),
            2e-4 * ((3_437_200.0 - r) / 7_500.0).exp()
        ) < 1e-14
    );
    assert_eq!(Exponential::mars_reference(R_MARS), e);
    assert!(Exponential::from_reference_radius(2e-4, 3_437_200.0, -1.0, R_MARS).is_err());
}

#[test]
fn least_squares_recovers_exact_exponential() {
    let truth = Exponential::new(1.7e-2, 0.0, 10_850.0).unwrap();
    let samples: Vec<(f64, f64)> = (0..=130)
        .map(|k| {
            let h = k as f64 * 1_000.0;
            (h, truth.density(h))
        })
        .collect();
    let fit = Exponential::fit_least_squares(&samples).unwrap();
    assert!(rel(fit.scale_height, truth.scale_height) < 1e-10, "{fit:?}");
    for h in [0.0_f64, 33e3, 130e3] {
        assert!(rel(fit.density(h), truth.density(h)) < 1e-10);
    }
    let at0 = fit.with_reference_altitude(0.0);
    assert!(rel(at0.rho_ref, truth.rho_ref) < 1e-10);
}

#[test]
fn exponential_fit_to_mean_profile_is_the_onboard_model() {
    // seed 001 §IV.A: the onboard model is a least-squares exponential fit to the mean profile.
    let mean = mars_mean_profile();
    let samples: Vec<(f64, f64)> = (10..=130)
        .map(|k| (k as f64 * 1e3, mean.density(k as f64 * 1e3)))
        .collect();
    let fit = Exponential::fit_least_squares(&samples).unwrap();
    let at41 = fit.with_reference_altitude(41e3);
    println!(
        "LSQ exponential fit to mars-mean over 10-130 km: rho(41 km) = {:.4e}, H = {:.1} m",
        at41.rho_ref, fit.scale_height
    );
    assert!((7_000.0..9_500.0).contains(&fit.scale_height));
    // Not exponential: the fit misses the profile by > 20 % somewhere in the fitted range.
    let worst = samples
        .iter()
        .map(|&(h, r)| rel(fit.density(h), r))
        .fold(0.0, f64::max);
    assert!(worst > 0.2, "worst {worst}");
}

#[test]
fn cospar_reduces_to_exponential() {
    let c = Cospar {
        rho0: 2e-4,
        h0: 41e3,
        beta: 1.0 / 7_500.0,
        gamma: 0.0,
        omega: 2e-4,
        delta: 0.0,
    };
    let e = Exponential::mars_reference(R_MARS);
    for h in [0.0_f64, 41e3, 80e3, 125e3] {
        assert!(rel(c.density(h), e.density(h)) < 1e-13, "h = {h}");
    }
    // With harmonics: eq. 17 term by term.
    let c2 = Cospar {
        gamma: 0.3,
        delta: -0.2,
        ..c
    };
    let h = 63e3_f64;
    let x = h - 41e3;
    let closed = 2e-4 * (-x / 7_500.0 + 0.3 * (2e-4 * x).cos() - 0.2 * (2e-4 * x).sin()).exp();
    assert!(rel(c2.density(h), closed) < 1e-14);
    let fd = fd_slope(&c2, h, 1.0);
    assert!(rel(ad_slope(&c2, h), fd) < 1e-6);
}

#[test]
fn cospar_default_tracks_mean_profile() {
    let c = Cospar::mars_default();
    let mean = mars_mean_profile();
    for k in (0..=150).step_by(10) {
        let h = k as f64 * 1e3;
        let e = rel(c.density(h), mean.density(h));
        assert!(e < 0.16, "h = {k} km: relative error {e}");
    }
    // The hard-coded coefficients are what the documented fit produces.
    let samples: Vec<(f64, f64)> = mean
        .altitudes_m()
        .iter()
        .map(|&h| (h, mean.density(h)))
        .collect();
    let tau = std::f64::consts::TAU;
    let fit = Cospar::fit_least_squares_scan(&samples, 0.0, tau / 1.0e6, tau / 5.0e4, 400).unwrap();
    for (a, b) in [
        (fit.rho0, c.rho0),
        (fit.beta, c.beta),
        (fit.gamma, c.gamma),
        (fit.omega, c.omega),
        (fit.delta, c.delta),
    ] {
        assert!(rel(a, b) < 1e-9, "refit {a} vs hard-coded {b}");
    }
}

// ---------------------------------------------------------------- spline

fn irregular_table() -> Tabulated {
    let alt = vec![0.0, 4e3, 10e3, 11e3, 25e3, 40e3, 41e3, 70e3, 100e3];
    let rho = vec![
        1.6e-2, 1.1e-2, 5.9e-3, 5.3e-3, 1.3e-3, 2.4e-4, 2.2e-4, 8.0e-6, 2.5e-7,
    ];
    Tabulated::new(alt, rho).unwrap()
}

#[test]
fn spline_reproduces_knots_exactly() {
    let t = irregular_table();
    for (h, r) in t.altitudes_m().iter().zip(t.knot_densities()) {
        assert!(rel(t.density(*h), r) < 1e-14, "h = {h}");
    }
    assert_eq!(t.altitude_range(), (0.0, 100e3));
    assert!(t.covers(10e3, 90e3));
    assert!(!t.covers(10e3, 120e3));
}

#[test]
fn spline_is_exact_for_exponential_table() {
    let e = Exponential::mars_reference(R_MARS);
    let alt: Vec<f64> = [0.0, 3e3, 9e3, 20e3, 24e3, 50e3, 77e3, 110e3, 150e3].to_vec();
    let rho: Vec<f64> = alt.iter().map(|&h| e.density(h)).collect();
    let t = Tabulated::new(alt, rho).unwrap();
    for k in 0..300 {
        let h = 0.37e3 + k as f64 * 499.3;
        assert!(rel(t.density(h), e.density(h)) < 1e-12, "h = {h}");
    }
    // Extrapolation continues the exponential (end log-slope).
    for h in [-5e3_f64, 180e3] {
        assert!(rel(t.density(h), e.density(h)) < 1e-12, "h = {h}");
    }
}

#[test]
fn spline_has_continuous_first_derivative() {
    let t = irregular_table();
    let knots = t.altitudes_m().to_vec();
    for &k in &knots[1..knots.len() - 1] {
        let left = ad_slope(&t, k - 1e-6);
        let right = ad_slope(&t, k + 1e-6);
        assert!(rel(left, right) < 1e-7, "knot {k}: {left} vs {right}");
    }
    // Also across the table ends into the extrapolation.
    for &k in &[knots[0], knots[knots.len() - 1]] {
        let (l, r) = (ad_slope(&t, k - 1e-6), ad_slope(&t, k + 1e-6));
        assert!(rel(l, r) < 1e-7, "end {k}: {l} vs {r}");
    }
}

#[test]
fn spline_ad_derivative_matches_finite_difference() {
    let t = irregular_table();
    for h in [1.3e3, 10.5e3, 33.3e3, 40.7e3, 85e3, 120e3, -3e3] {
        let (ad, fd) = (ad_slope(&t, h), fd_slope(&t, h, 0.5));
        assert!(rel(ad, fd) < 1e-6, "h = {h}: AD {ad} vs FD {fd}");
    }
}

#[test]
fn spline_accepts_descending_and_rejects_bad_tables() {
    let a = Tabulated::new(vec![0.0, 1e3, 2e3], vec![1e-2, 8e-3, 6e-3]).unwrap();
    let d = Tabulated::new(vec![2e3, 1e3, 0.0], vec![6e-3, 8e-3, 1e-2]).unwrap();
    assert_eq!(a, d);
    let dup = Tabulated::new(vec![0.0, 1e3, 1e3, 2e3], vec![1e-2, 8e-3, 7e-3, 6e-3]);
    assert!(matches!(dup, Err(AtmosphereError::InvalidTable { .. })));
    assert!(Tabulated::new(vec![0.0, 1e3], vec![1e-2, 8e-3]).is_err());
    assert!(Tabulated::new(vec![0.0, 1e3, 2e3], vec![1e-2, -8e-3, 6e-3]).is_err());
}

// ---------------------------------------------------------------- parsers

const CSV_FIXTURE: &str = "\
# Density profile exported from a spreadsheet
# columns: altitude above the MOLA sphere, total density

Height(km), DENSTOT (kg/m^3), Temp(K)
0.0, 1.55e-2, 195.0
10.0, 5.92e-3, 184.7
20.0, 2.14e-3, 176.3

40.0, 2.44e-4, 167.1
60.0, 2.57e-5, 164.0
# end of table
";

const GRAM_FIXTURE: &str = "\
#  Mars-GRAM 2010 style output (trajectory listing, descending)
  Time(sec) Height(km)  Lat(deg)  LonE(deg)   DENSTOT     Temp(K)  EWind  NWind
     0.0    125.000     -3.919    126.720    1.950E-08    143.1    12.0    -3.1
    20.0    100.000     -4.100    127.300    2.446E-07    137.4    10.5    -2.2
    40.0     80.000     -4.250    127.900    2.671D-06    155.2     8.0    -1.0
    60.0     60.000     -4.380    128.400    2.567E-05    164.0     5.1     0.4
    80.0     40.000     -4.490    128.800    2.442E-04    167.1     3.3     1.1
";

#[test]
fn csv_fixture_parses() {
    let t = parse_csv(CSV_FIXTURE, "profile.csv", &TableColumns::default()).unwrap();
    assert_eq!(t.num_knots(), 5);
    assert_eq!(t.altitude_range(), (0.0, 60e3));
    assert!(rel(t.density(40e3_f64), 2.44e-4) < 1e-14);
    assert!(rel(t.density(0.0_f64), 1.55e-2) < 1e-14);
}

#[test]
fn mars_gram_fixture_parses_descending_with_units_and_fortran_exponent() {
    let t = parse_mars_gram(GRAM_FIXTURE, "gram.txt", &TableColumns::default()).unwrap();
    assert_eq!(t.altitude_range(), (40e3, 125e3));
    assert!(rel(t.density(80e3_f64), 2.671e-6) < 1e-14);
    assert!(rel(t.density(125e3_f64), 1.95e-8) < 1e-14);
    let mid = t.density(70e3_f64);
    assert!(mid < 2.567e-5 && mid > 2.671e-6);
}

#[test]
fn aliases_and_explicit_columns() {
    let text = "Time Hgtkm Lat LonW Denlow Denavg Denhgh\n\
                0 10 0 0 5.0e-3 6.0e-3 7.0e-3\n\
                0 20 0 0 2.0e-3 2.2e-3 2.4e-3\n\
                0 30 0 0 7.0e-4 8.0e-4 9.0e-4\n";
    let t = parse_mars_gram(text, "Density.txt", &TableColumns::default()).unwrap();
    assert!(rel(t.density(20e3_f64), 2.2e-3) < 1e-14);
    let cols = TableColumns {
        density: "denhgh".into(),
        ..TableColumns::default()
    };
    let t = parse_mars_gram(text, "Density.txt", &cols).unwrap();
    assert!(rel(t.density(20e3_f64), 2.4e-3) < 1e-14);
    // Metres with a unit-declaring header.
    let m = "alt (m),rho\n0,1e-2\n500,9e-3\n1000,8e-3\n";
    let cols = TableColumns {
        height: "alt".into(),
        height_unit: HeightUnit::M,
        ..TableColumns::default()
    };
    let t = parse_csv(m, "m.csv", &cols).unwrap();
    assert_eq!(t.altitude_range(), (0.0, 1000.0));
}

/// Parse with both the CSV and the Mars-GRAM reader where the fixture allows, and return the
/// error message of the requested one.
fn csv_err(text: &str) -> (AtmosphereError, String) {
    let e = parse_csv(text, "bad.csv", &TableColumns::default()).unwrap_err();
    let msg = e.to_string();
    assert!(msg.contains("bad.csv"), "source missing in: {msg}");
    (e, msg)
}

#[test]
fn malformed_number_is_reported_with_line_and_column() {
    let text = "# c\nheight,denstot\n0,1e-2\n1,abc\n2,1e-3\n";
    let (e, msg) = csv_err(text);
    assert!(
        matches!(e, AtmosphereError::MalformedNumber { line: 4, .. }),
        "{e:?}"
    );
    assert!(
        msg.contains("line 4: column denstot: 'abc' is not a number"),
        "{msg}"
    );
    let (e, msg) = csv_err("height,denstot\n0,1e-2\n1,inf\n2,1e-3\n");
    assert!(
        matches!(e, AtmosphereError::NonFiniteNumber { line: 3, .. }),
        "{msg}"
    );
}

#[test]
fn missing_column_lists_header() {
    let (e, msg) = csv_err("alt,temperature\n0,200\n1,199\n2,198\n");
    assert!(
        matches!(e, AtmosphereError::MissingColumn { line: 1, .. }),
        "{e:?}"
    );
    assert!(
        msg.contains("line 1") && msg.contains("alt, temperature"),
        "{msg}"
    );
    assert!(
        msg.contains("hgtkm"),
        "aliases tried should be listed: {msg}"
    );
    // A non-default name gets no aliases.
    let cols = TableColumns {
        density: "DENS".into(),
        ..TableColumns::default()
    };
    let e = parse_mars_gram(GRAM_FIXTURE, "gram.txt", &cols).unwrap_err();
    let msg = e.to_string();
    assert!(
        msg.contains("gram.txt: line 2") && msg.contains("'DENS'") && msg.contains("DENSTOT"),
        "{msg}"
    );
}

#[test]
fn non_monotonic_and_duplicate_altitudes_name_both_lines() {
    let (e, msg) = csv_err("height,denstot\n0,1e-2\n1,9e-3\n0.5,8e-3\n");
    assert!(
        matches!(
            e,
            AtmosphereError::NonMonotonic {
                first_line: 3,
                second_line: 4,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(
        msg.contains("lines 3 and 4") && msg.contains("increasing"),
        "{msg}"
    );
    let (e, msg) = csv_err("height,denstot\n0,1e-2\n1,9e-3\n\n1,8e-3\n");
    assert!(
        matches!(
            e,
            AtmosphereError::NonMonotonic {
                first_line: 3,
                second_line: 5,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(msg.contains("repeats"), "{msg}");
}

#[test]
fn non_positive_density_too_few_rows_ragged_row_and_no_header() {
    let (e, msg) = csv_err("height,denstot\n0,1e-2\n1,0\n2,1e-3\n");
    assert!(
        matches!(e, AtmosphereError::NonPositiveDensity { line: 3, .. }),
        "{e:?}"
    );
    assert!(
        msg.contains("line 3") && msg.contains("not positive"),
        "{msg}"
    );
    let (e, msg) = csv_err("height,denstot\n0,1e-2\n1,5e-3\n");
    assert!(
        matches!(
            e,
            AtmosphereError::TooFewRows {
                found: 2,
                required: 3,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(msg.contains("found 2 data rows"), "{msg}");
    let (e, msg) = csv_err("height,denstot,temp\n0,1e-2,200\n1,5e-3\n2,1e-3,190\n");
    assert!(
        matches!(
            e,
            AtmosphereError::FieldCount {
                line: 3,
                expected: 3,
                found: 2,
                ..
            }
        ),
        "{e:?}"
    );
    assert!(msg.contains("line 3: expected 3 fields"), "{msg}");
    let (e, _) = csv_err("# only a comment\n\n");
    assert!(matches!(e, AtmosphereError::NoHeader { .. }));
    let e = parse_mars_gram(
        "Height DENSTOT\n1 1e-3\n2 5e-4 7\n3 1e-4\n",
        "g.txt",
        &TableColumns::default(),
    )
    .unwrap_err();
    assert!(
        e.to_string()
            .contains("g.txt: line 3: expected 2 fields (as in the header), found 3"),
        "{e}"
    );
}

#[test]
fn declared_height_unit_must_match() {
    let text = "Height(m),DENSTOT\n0,1e-2\n1000,9e-3\n2000,8e-3\n";
    let (e, msg) = csv_err(text);
    assert!(
        matches!(e, AtmosphereError::HeightUnitMismatch { .. }),
        "{e:?}"
    );
    assert!(
        msg.contains("declares unit m") && msg.contains("km"),
        "{msg}"
    );
}

proptest! {
    #![proptest_config(ProptestConfig {
        cases: 512,
        failure_persistence: None,
        ..ProptestConfig::default()
    })]

    #[test]
    fn parsers_never_panic_on_random_text(text in "\\PC*") {
        let _ = parse_csv(&text, "fuzz", &TableColumns::default());
        let _ = parse_mars_gram(&text, "fuzz", &TableColumns::default());
    }

    #[test]
    fn parsers_never_panic_on_table_like_text(
        rows in proptest::collection::vec(
            proptest::collection::vec(
                prop_oneof![
                    Just("height".to_string()), Just("DENSTOT".to_string()), Just("Height(km)".to_string()),
                    Just("(".to_string()), Just("[m]".to_string()), Just("#".to_string()), Just("".to_string()),
                    Just("nan".to_string()), Just("-1".to_string()), Just("1e400".to_string()),
                    (-1e3f64..1e3).prop_map(|x| x.to_string()),
                    "[a-zA-Z0-9().,#\\[\\] éД-]{0,6}",
                ],
                0..5,
            ),
            0..8,
        ),
        sep in prop_oneof![Just(","), Just(" "), Just("\t"), Just(", ")],
    ) {
        let text: String = rows.iter().map(|r| r.join(sep)).collect::<Vec<_>>().join("\n");
        let _ = parse_csv(&text, "fuzz", &TableColumns::default());
        let _ = parse_mars_gram(&text, "fuzz", &TableColumns::default());
        let gram = format!("#  Var_X DENSTOT Radius\n{text}");
        for datum in [None, Some(entrynav::atmosphere::Datum::Areoid)] {
            let placement = entrynav::atmosphere::Placement {
                datum,
                sphere_radius_m: R_MARS,
                latitude_rad: 0.5,
            };
            for format in [entrynav::atmosphere::TableFormat::Csv, entrynav::atmosphere::TableFormat::MarsGram] {
                let _ = entrynav::atmosphere::parse_profiles(&gram, "fuzz", format, &TableColumns::default(), &placement);
                let _ = entrynav::atmosphere::parse_profiles(&text, "fuzz", format, &TableColumns::default(), &placement);
            }
        }
    }
}

// ---------------------------------------------------------------- perturbed profiles

fn mean_model() -> AtmosphereModel {
    AtmosphereModel::Tabulated(mars_mean_profile())
}

fn corr(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len() as f64;
    let (ma, mb) = (a.iter().sum::<f64>() / n, b.iter().sum::<f64>() / n);
    let (mut sab, mut saa, mut sbb) = (0.0, 0.0, 0.0);
    for (x, y) in a.iter().zip(b) {
        sab += (x - ma) * (y - mb);
        saa += (x - ma) * (x - ma);
        sbb += (y - mb) * (y - mb);
    }
    sab / (saa * sbb).sqrt()
}

#[test]
fn perturbation_statistics_match_envelope() {
    let spec = PerturbationSpec::default();
    let mean = mean_model();
    let alts_km = [0.0, 40.0, 40.5, 50.0, 52.0, 60.0, 80.0, 90.0, 100.0];
    let n = 1000;
    let mut dev: Vec<Vec<f64>> = vec![Vec::with_capacity(n); alts_km.len()];
    for seed in 0..n as u64 {
        let p = Perturbed::from_seed(mean.clone(), &spec, seed).unwrap();
        for (j, &a) in alts_km.iter().enumerate() {
            let h = a * 1e3;
            let d = p.density(h) / mean.density(h) - 1.0;
            assert!((d - p.relative_deviation(h)).abs() < 1e-12);
            dev[j].push(d);
        }
    }
    let env = Envelope::default();
    for (j, &a) in alts_km.iter().enumerate() {
        let m = dev[j].iter().sum::<f64>() / n as f64;
        let sd = (dev[j].iter().map(|d| (d - m).powi(2)).sum::<f64>() / (n as f64 - 1.0)).sqrt();
        let sigma = env.sigma(a * 1e3);
        let se = sd / (n as f64).sqrt();
        println!(
            "{a:6.1} km: envelope {sigma:.4}  sample sd {sd:.4}  ratio {:.3}  mean factor − 1 = {m:+.5} ({:+.2} SE)",
            sd / sigma,
            m / se
        );
        assert!((sd / sigma - 1.0).abs() < 0.2, "{a} km: sd {sd} vs {sigma}");
        assert!(m.abs() < 3.0 * se, "{a} km: mean {m}, SE {se}");
    }
    let idx = |km: f64| alts_km.iter().position(|&a| a == km).unwrap();
    let c_near = corr(&dev[idx(50.0)], &dev[idx(52.0)]);
    let c_far = corr(&dev[idx(50.0)], &dev[idx(90.0)]);
    println!(
        "correlation 50/52 km = {c_near:.3} (theory ≈ {:.3}), 50/90 km = {c_far:.3}",
        (-0.25f64).exp()
    );
    assert!(c_near > 0.6, "{c_near}");
    assert!(c_far.abs() < 0.2, "{c_far}");
}

#[test]
fn same_seed_same_profile_scale_zero_is_mean() {
    let spec = PerturbationSpec::default();
    let a = Perturbed::from_seed(mean_model(), &spec, 42).unwrap();
    let b = Perturbed::from_seed(mean_model(), &spec, 42).unwrap();
    let c = Perturbed::from_seed(mean_model(), &spec, 43).unwrap();
    assert_eq!(a, b);
    assert_ne!(a.z_grid(), c.z_grid());
    for k in 0..300 {
        let h = k as f64 * 500.0 + 0.3;
        assert_eq!(a.density(h).to_bits(), b.density(h).to_bits());
    }
    let zero = PerturbationSpec {
        scale: 0.0,
        ..PerturbationSpec::default()
    };
    let p = Perturbed::from_seed(mean_model(), &zero, 42).unwrap();
    let mean = mean_model();
    for k in 0..300 {
        let h = k as f64 * 500.0 + 0.3;
        assert_eq!(p.density(h), mean.density(h));
    }
    // sample() with an invalid spec returns the mean instead of panicking; try_sample reports it.
    let bad = PerturbationSpec {
        correlation_length_m: -1.0,
        ..PerturbationSpec::default()
    };
    let mut rng = <rand_chacha::ChaCha8Rng as rand::SeedableRng>::seed_from_u64(1);
    let q = Perturbed::sample(mean_model(), &bad, &mut rng);
    assert_eq!(q.density(30e3_f64), mean.density(30e3_f64));
    assert!(Perturbed::try_sample(mean_model(), &bad, &mut rng).is_err());
}

#[test]
fn perturbed_ad_derivative_matches_finite_difference() {
    let p = Perturbed::from_seed(mean_model(), &PerturbationSpec::default(), 5).unwrap();
    // Off grid points and envelope corners (the factor is piecewise smooth on 1 km cells).
    for h in [12.3e3, 47.6e3, 71.2e3, 95.5e3, 118.4e3] {
        let (ad, fd) = (ad_slope(&p, h), fd_slope(&p, h, 0.05));
        assert!(rel(ad, fd) < 1e-5, "h = {h}: AD {ad} vs FD {fd}");
    }
}

// ---------------------------------------------------------------- configuration

fn no_files(name: &str) -> Result<String, entrynav::files::FileError> {
    Err(entrynav::files::FileError::new(name, "no such file"))
}

fn atm(toml_text: &str) -> Result<AtmosphereConfig, toml::de::Error> {
    toml::from_str(toml_text)
}

#[test]
fn config_builds_every_model() {
    let planet = Planet::MARS;
    let e = atm(
        "model = 'exponential'\nrho_ref_kgm3 = 2e-4\nref_radius_km = 3437.2\nscale_height_km = 7.5",
    )
    .unwrap();
    e.validate("truth.atmosphere").unwrap();
    assert_eq!(e.reference_density(), Some(2e-4));
    let m = e.build(&planet, &no_files).unwrap();
    assert!(rel(m.density(41e3_f64), 2e-4) < 1e-12);

    let c = atm("model = 'cospar'\nrho0_kgm3 = 2e-4\nref_altitude_km = 41\nbeta_per_km = 0.13333333333333333\ngamma = 0\nomega_per_km = 0.2\ndelta = 0").unwrap();
    let m = c.build(&planet, &no_files).unwrap();
    assert!(
        rel(
            m.density(80e3_f64),
            Exponential::mars_reference(planet.radius).density(80e3)
        ) < 1e-12
    );
    assert_eq!(c.reference_density(), None);

    let mm = atm("model = 'mars-mean'").unwrap();
    let m = mm.build(&planet, &no_files).unwrap();
    assert!(m.covers(0.0, 150e3) && !m.covers(0.0, 151e3));

    let t = atm("model = 'table'\nfile = 'gram.txt'\nformat = 'mars-gram'").unwrap();
    let load = |name: &str| {
        if name == "gram.txt" {
            Ok(GRAM_FIXTURE.to_string())
        } else {
            Err(entrynav::files::FileError::new(name, "not found"))
        }
    };
    let m = t.build(&planet, &load).unwrap();
    assert!(rel(m.density(60e3_f64), 2.567e-5) < 1e-14);

    // The named column is the one read: a temperature column as density is picked, and then
    // refused by the physical density envelope, naming the file, line and column.
    let t = atm("model = 'table'\nfile = 'p.csv'\nformat = 'csv'\nheight_column = 'height'\ndensity_column = 'temp'\nheight_unit = 'km'").unwrap();
    let load = |_: &str| Ok(CSV_FIXTURE.to_string());
    let err = t.build(&planet, &load).unwrap_err().to_string();
    assert!(
        err.contains("p.csv") && err.contains("Temp(K)") && err.contains("195"),
        "{err}"
    );
    assert!(err.contains("physical envelope"), "{err}");
}

#[test]
fn config_rejects_unknown_fields_and_missing_tag() {
    let cases = [
        "model = 'exponential'\nrho_ref_kgm3 = 2e-4\nref_radius_km = 3437.2\nscale_height_km = 7.5\nscale_hieght_km = 7",
        "model = 'mars-mean'\nrho = 1",
        "model = 'table'\nfile = 'x'\nformat = 'csv'\ncolumns = 3",
        "model = 'cospar'\nrho0_kgm3 = 2e-4\nref_altitude_km = 41\nbeta_per_km = 0.1\ngamma = 0\nomega_per_km = 0.2\ndelta = 0\nepsilon = 1",
        "model = 'isothermal'",
        "rho_ref_kgm3 = 2e-4",
        "model = 'table'\nfile = 'x'\nformat = 'json'",
    ];
    for text in cases {
        let r = atm(text);
        assert!(r.is_err(), "accepted: {text}");
        println!(
            "{}",
            r.unwrap_err().to_string().lines().last().unwrap_or("")
        );
    }
    let r = atm(
        "model = 'exponential'\nrho_ref_kgm3 = 2e-4\nref_radius_km = 3437.2\nscale_height_km = 7.5\nextra = 1",
    );
    assert!(r.unwrap_err().to_string().contains("extra"));

    let p: Result<PerturbationConfig, _> =
        toml::from_str("scale = 1\ncorrelation_km = 8\nsigma = 0.1");
    assert!(p.is_err());
    let p: PerturbationConfig = toml::from_str("correlation_km = 6").unwrap();
    assert_eq!(p.scale, 1.0);
    assert_eq!(p.to_spec().correlation_length_m, 6e3);
    assert_eq!(p.to_spec().envelope, Envelope::default());
}

#[test]
fn config_range_errors_name_field_value_and_range() {
    let bad = atm(
        "model = 'exponential'\nrho_ref_kgm3 = -1\nref_radius_km = 3437.2\nscale_height_km = 7.5",
    )
    .unwrap();
    let msg = bad.validate("truth.atmosphere").unwrap_err().to_string();
    assert_eq!(
        msg,
        "truth.atmosphere.rho_ref_kgm3 = -1 is out of range: must be > 0 and < 1"
    );
    let bad = atm(
        "model = 'exponential'\nrho_ref_kgm3 = 2e-4\nref_radius_km = 3437.2\nscale_height_km = 0",
    )
    .unwrap();
    let msg = bad.validate("filter.atmosphere").unwrap_err().to_string();
    assert!(
        msg.starts_with("filter.atmosphere.scale_height_km = 0 is out of range"),
        "{msg}"
    );
    // A radius given as an altitude is caught at build time.
    let bad = atm(
        "model = 'exponential'\nrho_ref_kgm3 = 2e-4\nref_radius_km = 41\nscale_height_km = 7.5",
    )
    .unwrap();
    let msg = bad.build(&Planet::MARS, &no_files).unwrap_err().to_string();
    assert!(
        msg.contains("ref_radius_km = 41") && msg.contains("not an altitude"),
        "{msg}"
    );

    let bad = atm("model = 'table'\nfile = 'missing.csv'\nformat = 'csv'").unwrap();
    let e = bad.build(&Planet::MARS, &no_files).unwrap_err();
    assert!(matches!(&e, AtmosphereError::LoadFailed { file, .. } if file == "missing.csv"));
    assert!(e.to_string().contains("'missing.csv'"), "{e}");
    // Parse errors inside a loaded table name the file.
    let bad = atm("model = 'table'\nfile = 'broken.csv'\nformat = 'csv'").unwrap();
    let e = bad
        .build(&Planet::MARS, &|_: &str| {
            Ok("height,denstot\n0,x\n".to_string())
        })
        .unwrap_err();
    assert!(e.to_string().starts_with("broken.csv: line 2"), "{e}");

    let p = PerturbationConfig {
        scale: -0.5,
        ..PerturbationConfig::default()
    };
    let msg = p.validate("truth.perturbation").unwrap_err().to_string();
    assert!(
        msg.starts_with("truth.perturbation.scale = -0.5 is out of range"),
        "{msg}"
    );
    let p = PerturbationConfig {
        envelope: Some(vec![[0.0, 0.02], [40.0, 0.05], [30.0, 0.1]]),
        ..PerturbationConfig::default()
    };
    let msg = p.validate("truth.perturbation").unwrap_err().to_string();
    assert!(msg.contains("truth.perturbation.envelope[2]"), "{msg}");
    let p = PerturbationConfig {
        envelope: Some(vec![[0.0, 0.02], [40.0, 0.05], [80.0, 0.2]]),
        correlation_km: 4.0,
        ..PerturbationConfig::default()
    };
    let m = p.apply(mean_model(), 9, "truth.perturbation").unwrap();
    assert_eq!(m.kind(), "perturbed");
}
