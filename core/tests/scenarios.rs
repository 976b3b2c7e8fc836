//! Scenario files: built-ins are valid, round-trip, and bad input gets a clear error.

use entrynav::scenario::{BUILTIN_NAMES, Scenario, ScenarioConfig, ScenarioError};

fn no_files(p: &str) -> Result<String, entrynav::files::FileError> {
    Err(entrynav::files::FileError::new(
        p,
        "no such file (test loader)",
    ))
}

#[test]
fn every_builtin_parses_validates_builds_and_round_trips() {
    for name in BUILTIN_NAMES {
        let cfg = ScenarioConfig::builtin(name).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(cfg.name, name, "file name and `name` field agree");
        let text = cfg.to_toml_string();
        let again = ScenarioConfig::from_toml_str(&text, "roundtrip")
            .unwrap_or_else(|e| panic!("{name} round trip: {e}"));
        assert_eq!(cfg, again, "{name}: TOML round trip changes the scenario");
        let sc = Scenario::build(cfg, &no_files).unwrap_or_else(|e| panic!("{name}: build: {e}"));
        assert_eq!(
            sc.onboard.initial_estimate.len(),
            sc.filter_model().state_dim()
        );
        assert!(!sc.channels.is_empty(), "{name} has no measurement channel");
    }
}

#[test]
fn the_scenarios_folder_holds_exactly_the_builtins() {
    // The built-ins are embedded from core/scenarios/; a scenario file added there but not
    // listed (or listed but missing) would be silently unreachable by name.
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("scenarios");
    let mut on_disk: Vec<String> = std::fs::read_dir(&dir)
        .expect("core/scenarios exists")
        .filter_map(|e| e.ok()?.file_name().into_string().ok())
        .filter(|n| n.ends_with(".toml") && !n.contains("-density-nn"))
        .map(|n| n.trim_end_matches(".toml").to_string())
        .collect();
    on_disk.sort();
    let mut listed: Vec<String> = BUILTIN_NAMES.iter().map(|s| s.to_string()).collect();
    listed.sort();
    assert_eq!(on_disk, listed);
}

fn base() -> String {
    entrynav::scenario::builtin_toml("four-beacon-fusion")
        .unwrap()
        .to_string()
}

/// Apply `edit` to the four-beacon-fusion text and return the error message.
fn error_of(edit: impl Fn(String) -> String) -> String {
    let text = edit(base());
    match ScenarioConfig::from_toml_str(&text, "edited.toml") {
        Ok(_) => panic!("edited scenario was accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn unknown_field_is_refused_with_its_name() {
    let msg = error_of(|s| s.replace("[truth.vehicle]\n", "[truth.vehicle]\nmass_kg = 900.0\n"));
    assert!(msg.contains("mass_kg"), "{msg}");
    assert!(msg.contains("edited.toml"), "{msg}");
    let msg = error_of(|s| {
        s.replace(
            "ignore_visibility = true",
            "ignore_visibility = true\nfoo = 1",
        )
    });
    assert!(msg.contains("foo"), "{msg}");
}

#[test]
fn negative_mass_is_refused() {
    // A negative mass shows up as a negative C_D S/m or ballistic coefficient.
    let msg = error_of(|s| s.replacen("cd_s_over_m_m2kg = 0.016", "cd_s_over_m_m2kg = -0.016", 1));
    assert!(
        msg.contains("truth.vehicle.cd_s_over_m_m2kg")
            && msg.contains("-0.016")
            && msg.contains("> 0"),
        "{msg}"
    );
    let msg = error_of(|s| {
        s.replacen(
            "cd_s_over_m_m2kg = 0.016",
            "ballistic_coefficient_kgm2 = -146.0",
            1,
        )
    });
    assert!(
        msg.contains("ballistic_coefficient_kgm2") && msg.contains("-146"),
        "{msg}"
    );
}

#[test]
fn non_positive_density_is_refused() {
    let msg = error_of(|s| s.replacen("rho_ref_kgm3 = 2e-4", "rho_ref_kgm3 = 0.0", 1));
    assert!(msg.contains("truth.atmosphere.rho_ref_kgm3"), "{msg}");
    let msg = error_of(|s| s.replacen("rho_ref_kgm3 = 2e-4", "rho_ref_kgm3 = -2e-4", 1));
    assert!(
        msg.contains("rho_ref_kgm3") && msg.contains("-0.0002"),
        "{msg}"
    );
}

#[test]
fn non_positive_duration_is_refused() {
    for bad in ["0.0", "-300.0"] {
        let msg = error_of(|s| s.replace("duration_s = 300.0", &format!("duration_s = {bad}")));
        assert!(
            msg.contains("timing.duration_s") && msg.contains("must be > 0"),
            "{msg}"
        );
    }
}

#[test]
fn malformed_number_is_refused_with_line() {
    let msg = error_of(|s| s.replace("duration_s = 300.0", "duration_s = 3x0.0"));
    assert!(msg.contains("edited.toml") && msg.contains("line"), "{msg}");
    let msg = error_of(|s| s.replace("speed_mps = 5515.0", "speed_mps = \"fast\""));
    assert!(
        msg.contains("line") && msg.contains("speed_mps") || msg.contains("invalid type"),
        "{msg}"
    );
}

#[test]
fn missing_table_file_is_refused_with_the_file_name() {
    let text = base().replacen(
        "model = \"exponential\"\nrho_ref_kgm3 = 2e-4\nref_radius_km = 3437.2\nscale_height_km = 7.5",
        "model = \"table\"\nfile = \"does-not-exist.csv\"\nformat = \"csv\"",
        1,
    );
    let cfg =
        ScenarioConfig::from_toml_str(&text, "table.toml").expect("valid until the file is read");
    let err = Scenario::build(cfg, &no_files).expect_err("missing file must fail");
    let msg = err.to_string();
    assert!(msg.contains("does-not-exist.csv"), "{msg}");
    assert!(matches!(err, ScenarioError::Atmosphere(_)));
}

#[test]
fn structural_errors_name_the_field() {
    let q_line = base()
        .lines()
        .find(|l| l.starts_with("q_diag = "))
        .unwrap()
        .to_string();
    let msg = error_of(|s| s.replace(&q_line, "q_diag = [1.0]"));
    assert!(msg.contains("filter.q_diag") && msg.contains("11"), "{msg}");
    // Augmented and consider states: duplicates, two density scales, biases without an IMU, a
    // start value out of range, a bad Gauss-Markov time constant, a bad noise factor.
    let augment = "augment = [\"rho0\", \"lift-to-drag\", \"accel-bias-x\", \"accel-bias-y\", \"accel-bias-z\"]";
    assert!(base().contains(augment));
    let msg = error_of(|s| {
        s.replace(
            augment,
            &format!("{augment}\nconsider = [\"rho0\"]\ninitial_consider = [2e-4]"),
        )
    });
    assert!(
        msg.contains("listed twice") && msg.contains("rho0"),
        "{msg}"
    );
    let msg = error_of(|s| {
        s.replace(augment, "augment = [\"rho0\", \"lift-to-drag\", \"accel-bias-x\", \"accel-bias-y\", \"density-bias\"]")
    });
    assert!(msg.contains("rho0 and density-bias"), "{msg}");
    let msg = error_of(|s| s.replace("0.17, 0.0, 0.0, 0.0]", "0.17, 0.0, 0.0, 20.0]"));
    assert!(
        msg.contains("filter.initial_augmented[4]") && msg.contains("10"),
        "{msg}"
    );
    let msg = error_of(|s| {
        s.replace(
            "dynamics = \"spherical\"\n# Seed 000's",
            "dynamics = \"spherical\"\naccel_bias_tau_s = -5.0\n# Seed 000's",
        )
    });
    assert!(msg.contains("filter.accel_bias_tau_s"), "{msg}");
    let msg = error_of(|s| {
        s.replace(
            "[filter.vehicle]",
            "[filter.noise_inflation]\nrange = 0.0\n\n[filter.vehicle]",
        )
    });
    assert!(msg.contains("filter.noise_inflation.range"), "{msg}");
    let aero = |body: &str| {
        let body = body.to_string();
        move |s: String| {
            s.replace(
                "[filter.vehicle]",
                &format!(
                    "[filter.process_noise]\nmodel = \"aero-scaled\"\n{body}\n\n[filter.vehicle]"
                ),
            )
        }
    };
    let msg = error_of(aero("fraction = [0.05, 0.0, 0.0]"));
    assert!(
        msg.contains("filter.process_noise") && msg.contains("correlation_time_s"),
        "{msg}"
    );
    let msg = error_of(aero(
        "fraction = [0.05, 20.0, 0.0]\ncorrelation_time_s = 5.0",
    ));
    assert!(msg.contains("filter.process_noise.fraction[1]"), "{msg}");
    let msg = error_of(aero(
        "fraction = [0.05, 0.0, 0.0]\ncorrelation_length_m = -8000.0",
    ));
    assert!(
        msg.contains("filter.process_noise.correlation_length_m"),
        "{msg}"
    );
    let msg = error_of(|s| s.replacen("heading_deg = 5.156\n", "", 1));
    assert!(
        msg.contains("truth.initial") && msg.contains("heading_deg"),
        "{msg}"
    );
    let msg = error_of(|s| s.replacen("truth_step_s = 0.1", "truth_step_s = 0.3", 1));
    assert!(msg.contains("multiple"), "{msg}");
    let msg = error_of(|s| s.replacen("lat_deg = -28.02", "lat_deg = 95.0", 1));
    assert!(
        msg.contains("truth.initial.lat_deg") && msg.contains("95"),
        "{msg}"
    );
    let msg = error_of(|s| s.replacen("radius_km = 3518.2", "radius_km = 3000.0", 1));
    assert!(
        msg.contains("truth.initial.radius_km") && msg.contains("> the surface = 3396.2"),
        "{msg}"
    );
}

#[test]
fn random_text_never_panics() {
    // A crude fuzz: every prefix of a valid file must give Ok or an Err, never a panic.
    let text = base();
    let mut cut = 0;
    while cut < text.len() {
        if text.is_char_boundary(cut) {
            let _ = ScenarioConfig::from_toml_str(&text[..cut], "prefix");
        }
        cut += 97;
    }
}

/// A 3-vector with 2, 4 or 10 000 numbers is refused naming the field and the count, never cut
/// to 3 (the base result and fingerprint were what such a file gave before).
#[test]
fn a_fixed_length_array_of_another_length_is_refused() {
    let orbiters = entrynav::scenario::builtin_toml("orbiters-3").unwrap();
    let cases = [
        (
            orbiters,
            "velocity_mps = [5775.31, 1124.27, 1175.48]",
            "velocity_mps = [5775.31, 1124.27, 1175.48, 1.0]",
            "4",
        ),
        (
            orbiters,
            "velocity_mps = [0.5, 0.5, 0.5]",
            "velocity_mps = [0.5, 0.5]",
            "2",
        ),
        (
            entrynav::scenario::builtin_toml("four-beacon-fusion").unwrap(),
            "bias_mps2 = [-0.03, -0.03, -0.03]",
            &format!("bias_mps2 = [{}]", vec!["-0.03"; 10_000].join(", ")),
            "10000",
        ),
    ];
    for (text, from, to, count) in cases {
        assert!(text.contains(from), "{from}");
        let err = ScenarioConfig::from_toml_str(&text.replacen(from, to, 1), "edited.toml")
            .map(|_| ())
            .expect_err(to);
        let err = err.to_string();
        let field = from.split(' ').next().unwrap();
        assert!(
            err.contains(field)
                && err.contains(&format!("invalid length {count}"))
                && err.contains("exactly 3 numbers"),
            "{err}"
        );
    }
}
