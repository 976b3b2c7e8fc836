//! End-to-end tests of the `entrynav` binary.

mod common;
use common::entrynav;
use std::process::Command;

fn tmpdir(name: &str) -> std::path::PathBuf {
    common::scratch_dir("cli", name)
}

#[test]
fn scenarios_lists_the_seven_builtins() {
    let (code, out, _) = entrynav(&["scenarios"]);
    assert_eq!(code, 0);
    for name in [
        "four-beacon-fusion",
        "four-beacon-fusion-fault",
        "msl-airdata",
        "ground-beacons-3",
        "orbiters-3",
        "msl-pressure",
        "msl-pressure-orbiter",
    ] {
        assert!(
            out.lines().any(|l| l.starts_with(name)),
            "{name} missing from:\n{out}"
        );
    }
    // One line each on what the scenario is, its paper by name (not "seed 000", which reads like
    // the RNG seed) and why line of sight is ignored where it is.
    let line = |n: &str| {
        out.lines()
            .find(|l| l.split_whitespace().next() == Some(n))
            .unwrap_or_else(|| panic!("{n} missing"))
            .to_string()
    };
    let fusion = line("four-beacon-fusion");
    for part in [
        "[P0]",
        "11 spherical states",
        "IMU + 4 range",
        "2 surface beacons + 2 orbiters",
        "300 s",
        "line of sight ignored",
    ] {
        assert!(fusion.contains(part), "{part}: {fusion}");
    }
    assert!(line("orbiters-3").contains("6 Cartesian states; 3 range; 3 orbiters; 240 s"));
    assert!(line("msl-airdata").contains("IMU + dynamic pressure + heating; no beacons"));
    assert!(!line("ground-beacons-3").contains("line of sight ignored"));
    assert!(
        !out.contains("seed 00") && !out.contains("SPEC.md"),
        "{out}"
    );
    let refs = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../docs/references.md"
    ))
    .expect("docs/references.md");
    for p in ["[P0]", "[P1]", "[P2]", "[P3]", "10.5772/intechopen.73605"] {
        assert!(refs.contains(p), "docs/references.md lacks {p}");
    }
}

#[test]
fn scenario_show_prints_toml_that_simulates_the_same() {
    let dir = tmpdir("show");
    let (code, toml_text, _) = entrynav(&["scenario", "show", "four-beacon-fusion-fault"]);
    assert_eq!(code, 0);
    let file = dir.join("copy.toml");
    std::fs::write(&file, &toml_text).unwrap();
    let a = dir.join("a.csv");
    let b = dir.join("b.csv");
    let (c1, _, e1) = entrynav(&[
        "simulate",
        "--scenario",
        "four-beacon-fusion-fault",
        "--seed",
        "5",
        "--out",
        a.to_str().unwrap(),
    ]);
    let (c2, _, e2) = entrynav(&[
        "simulate",
        "--scenario",
        file.to_str().unwrap(),
        "--seed",
        "5",
        "--out",
        b.to_str().unwrap(),
    ]);
    assert_eq!((c1, c2), (0, 0), "{e1}{e2}");
    assert_eq!(
        std::fs::read(&a).unwrap(),
        std::fs::read(&b).unwrap(),
        "shown TOML must reproduce the built-in"
    );
}

#[test]
fn scenario_show_prints_the_builtin_file_as_written_and_resolved_on_request() {
    let (code, text, err) = entrynav(&["scenario", "show", "four-beacon-fusion"]);
    assert_eq!(code, 0, "{err}");
    // Comments and one-line arrays survive, so a tutorial's `sed` finds the beacon.
    assert!(text.contains("# Table 2"), "comments lost");
    assert_eq!(
        text.lines()
            .filter(|l| l.trim() == "position_km = [3300.0, 420.0, 1350.0]")
            .count(),
        1,
        "{text}"
    );
    let (code, resolved, err) = entrynav(&["scenario", "show", "four-beacon-fusion", "--resolved"]);
    assert_eq!(code, 0, "{err}");
    assert!(!resolved.contains('#') && resolved.contains("four-beacon-fusion"));
    assert_ne!(text, resolved);
}

#[test]
fn simulate_writes_the_documented_columns_and_summary() {
    let dir = tmpdir("sim");
    let csv = dir.join("out/msl.csv");
    let (code, out, err) = entrynav(&[
        "simulate",
        "--scenario",
        "msl-airdata",
        "--out",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    for key in [
        "final altitude",
        "final speed",
        "peak decel",
        "peak dyn. press",
        "peak heating",
    ] {
        assert!(out.contains(key), "summary lacks '{key}':\n{out}");
    }
    let (header, cells) = read_csv(&csv);
    for col in [
        "t_s",
        "r_m",
        "lon_rad",
        "lat_rad",
        "v_mps",
        "fpa_rad",
        "heading_rad",
        "altitude_m",
        "density_kgm3",
        "dynamic_pressure_pa",
        "accel_x_mps2",
        "accel_y_mps2",
        "accel_z_mps2",
        "dynamic_pressure_meas_pa",
        "heating_meas_wm2",
    ] {
        assert!(
            header.iter().any(|h| h == col),
            "missing column {col} in {header:?}"
        );
    }
    let rows: Vec<Vec<f64>> = cells
        .iter()
        .map(|l| {
            l.iter()
                .map(|c| {
                    if c.is_empty() {
                        f64::NAN
                    } else {
                        c.parse().unwrap()
                    }
                })
                .collect()
        })
        .collect();
    assert_eq!(
        rows.len(),
        1401,
        "t = 0 plus 1400 samples at 4 Hz over 350 s"
    );
    let t_last = rows.last().unwrap()[0];
    assert!((t_last - 350.0).abs() < 1e-9);
    // Every number written is finite (measurement slots may be empty only at t = 0).
    for r in &rows[1..] {
        assert!(r.iter().all(|v| v.is_finite()), "non-finite value in {r:?}");
    }
}

#[test]
fn bad_inputs_fail_cleanly_with_exit_code_2() {
    let dir = tmpdir("bad");
    let (code, _, err) = entrynav(&["simulate", "--scenario", "no-such-scenario"]);
    assert_eq!(code, 2);
    assert!(
        err.contains("no-such-scenario") && err.contains("four-beacon-fusion"),
        "{err}"
    );

    let bad = dir.join("bad.toml");
    let (_, text, _) = entrynav(&["scenario", "show", "four-beacon-fusion"]);
    std::fs::write(
        &bad,
        text.replacen("duration_s = 300.0", "duration_s = -1.0", 1),
    )
    .unwrap();
    let (code, _, err) = entrynav(&["simulate", "--scenario", bad.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(
        err.contains("timing.duration_s") && err.contains("-1"),
        "{err}"
    );
    assert!(!err.contains("panicked"), "{err}");
}

#[test]
fn trade_writes_the_documented_json_csv_and_plots() {
    let dir = tmpdir("trade");
    let json = dir.join("t.json");
    let csv = dir.join("csv");
    let plots = dir.join("plots");
    let (code, out, err) = entrynav(&[
        "trade",
        "--scenario",
        "four-beacon-fusion-fault",
        "--filters",
        "ekf,dcifaif",
        "--runs",
        "6",
        "--seed",
        "3",
        "--quiet",
        "--json",
        json.to_str().unwrap(),
        "--csv-dir",
        csv.to_str().unwrap(),
        "--plots",
        plots.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("filter ekf") && out.contains("filter dcifaif") && out.contains("ANEES"),
        "{out}"
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(v["scenario"], "four-beacon-fusion-fault");
    assert_eq!(v["runs"], 6);
    assert_eq!(v["seed"], 3);
    let filters = v["filters"].as_array().unwrap();
    assert_eq!(filters.len(), 2);
    for f in filters {
        for key in [
            "name",
            "rmse_time_avg",
            "rmse_final",
            "anees",
            "nees_in_bounds_frac",
            "diverged",
            "density_rmspe_pct",
            "ellipse_km",
        ] {
            assert!(f.get(key).is_some(), "JSON filter entry lacks {key}: {f}");
        }
        assert!(
            f.get("us_per_step").is_none(),
            "timing outside `timing`: {f}"
        );
        let name = f["name"].as_str().unwrap();
        assert!(
            v["timing"]["us_per_step"][name].as_f64().unwrap() > 0.0,
            "{}",
            v["timing"]
        );
        for state in [
            "r_m",
            "lon_rad",
            "lat_rad",
            "v_mps",
            "fpa_rad",
            "heading_rad",
            "pos_m",
            "vel_mps",
        ] {
            assert!(
                f["rmse_time_avg"][state].is_number(),
                "{state} missing in {}",
                f["rmse_time_avg"]
            );
        }
        assert!(
            f["ellipse_km"]["semi_major_km"].as_f64().unwrap()
                >= f["ellipse_km"]["semi_minor_km"].as_f64().unwrap()
        );
    }
    assert!(
        filters[1]["density_rmspe_pct"].is_number(),
        "rho0 is a state: density is estimated"
    );
    let series = std::fs::read_to_string(csv.join("four-beacon-fusion-fault_dcifaif.csv")).unwrap();
    assert_eq!(series.lines().count(), 301, "header + 300 epochs");
    assert!(series.lines().next().unwrap().contains("weight_3"));
    for f in [
        "four-beacon-fusion-fault_rmse_r_m.svg",
        "four-beacon-fusion-fault_nees.svg",
        "four-beacon-fusion-fault_dcifaif_weights.svg",
        "four-beacon-fusion-fault_ekf_nis_channels.svg",
    ] {
        let svg = std::fs::read_to_string(plots.join(f)).unwrap_or_else(|e| panic!("{f}: {e}"));
        assert!(
            svg.starts_with("<svg") && svg.contains("<path") || svg.contains("<polyline"),
            "{f} has no curve"
        );
    }
    // The per-channel NIS figure has a curve per measured channel, named by the channel.
    let ch = std::fs::read_to_string(plots.join("four-beacon-fusion-fault_ekf_nis_channels.svg"))
        .unwrap();
    for name in ["range_surface-1_m", "range_orbiter-2_m", "accel_x_mps2"] {
        assert!(ch.contains(name), "no {name} curve in the channel figure");
    }
    // And the JSON gives each channel's share of epochs inside its band.
    let band = &filters[0]["nis_per_channel"]["range_surface-1_m"]["epochs_in_band_frac"];
    assert!(
        band.as_f64().is_some_and(|b| (0.0..=1.0).contains(&b)),
        "{band}"
    );
}

#[test]
fn trade_refuses_unknown_and_unfit_filters() {
    let (code, _, err) = entrynav(&[
        "trade",
        "--scenario",
        "msl-airdata",
        "--filters",
        "ekf,kalman9000",
        "--runs",
        "2",
    ]);
    assert_eq!(code, 2);
    assert!(
        err.contains("kalman9000") && err.contains("dcifaif"),
        "{err}"
    );
    let (code, _, err) = entrynav(&[
        "trade",
        "--scenario",
        "msl-airdata",
        "--filters",
        "dcifaif",
        "--runs",
        "2",
    ]);
    assert_eq!(code, 2);
    assert!(
        err.contains("beacon") && err.contains("filters that fit"),
        "{err}"
    );
    let (code, _, err) = entrynav(&[
        "trade",
        "--scenario",
        "msl-pressure",
        "--set",
        "truth.density_bias=-3",
        "--runs",
        "2",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("truth.density_bias"), "{err}");
}

#[test]
fn observe_reports_raw_and_scaled_degree_and_json() {
    let dir = tmpdir("observe");
    let json = dir.join("o.json");
    let plot = dir.join("o.svg");
    let (code, out, err) = entrynav(&[
        "observe",
        "--scenario",
        "four-beacon-fusion",
        "--subsystems",
        "--step",
        "10",
        "--json",
        json.to_str().unwrap(),
        "--plot",
        plot.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("RAW") && out.contains("SCALED"), "{out}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    for key in [
        "method",
        "times_s",
        "delta",
        "delta_min",
        "delta_max",
        "t_delta_min_s",
        "elapsed_s",
        "scaling",
        "subsystems",
    ] {
        assert!(v.get(key).is_some(), "observe JSON lacks {key}");
    }
    let central_min = v["delta_min"].as_f64().unwrap();
    assert!(central_min > 0.0);
    for s in v["subsystems"].as_array().unwrap() {
        assert!(
            s["delta_max"].as_f64().unwrap() < central_min,
            "a subsystem is not weaker than the centralised system"
        );
    }
    assert!(std::fs::read_to_string(&plot).unwrap().starts_with("<svg"));
    let (code, _, err) = entrynav(&["observe", "--scenario", "msl-airdata", "--fim"]);
    assert_eq!(code, 2);
    assert!(err.contains("beacon"), "{err}");
}

#[test]
fn observe_pcrlb_bounds_the_scenario_without_a_filter() {
    let dir = tmpdir("observe-pcrlb");
    let json = dir.join("o.json");
    let args = |runs: &str| {
        vec![
            "observe".to_string(),
            "--scenario".into(),
            "ground-beacons-3".into(),
            "--step".into(),
            "20".into(),
            "--pcrlb".into(),
            "--runs".into(),
            runs.into(),
            "--json".into(),
            json.to_str().unwrap().into(),
        ]
    };
    let a = args("20");
    let (code, out, err) = entrynav(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("PCRLB over 20 truth runs"), "{out}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let b = &v["pcrlb"];
    assert_eq!(b["available"], true, "{b}");
    let (avg, fin) = (
        b["time_avg"]["pos_m"].as_f64().unwrap(),
        b["final"]["pos_m"].as_f64().unwrap(),
    );
    // Table 4's 1 km-scale initial errors shrink under three ranging beacons to tens of metres.
    assert!(
        fin > 1.0 && fin < avg && avg < 1000.0,
        "avg {avg} m, final {fin} m"
    );
    let a = args("0");
    let (code, _, err) = entrynav(&a.iter().map(String::as_str).collect::<Vec<_>>());
    assert_ne!(code, 0);
    assert!(
        err.contains("invalid value '0' for '--runs") && err.contains("1 to 10000000"),
        "{err}"
    );
}

#[test]
fn grid_runs_every_cell_and_refuses_unfit_filters() {
    let dir = tmpdir("grid");
    let grid = dir.join("g.toml");
    std::fs::write(
        &grid,
        "name = \"g\"\nruns = 4\nseed = 2\nfilters = [\"ekf\", \"dcifaif\"]\nscenarios = [\"four-beacon-fusion\"]\n\
         [variations]\nbeacons = [1, 4]\nnoise_scale = [1.0, 3.0]\n",
    )
    .unwrap();
    let out = dir.join("report");
    let (code, _, err) = entrynav(&[
        "trade",
        "--grid",
        grid.to_str().unwrap(),
        "--out-dir",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    let md = std::fs::read_to_string(out.join("g.md")).unwrap();
    assert_eq!(md.matches("| c0").count(), 8, "4 cells × 2 filters:\n{md}");
    assert!(
        md.contains("1 beacons, noise x3") && md.contains("refused"),
        "{md}"
    );
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(out.join("g.json")).unwrap()).unwrap();
    let cells = v["cells"].as_array().unwrap();
    let pos = |variation: &str| {
        cells
            .iter()
            .find(|c| c["variation"] == variation && c["filter"] == "ekf")
            .unwrap()["pos_rmse_avg_m"]
            .as_f64()
            .unwrap()
    };
    assert!(
        pos("4 beacons, noise x3") > pos("4 beacons, noise x1"),
        "more noise must cost accuracy"
    );
    assert!(out.join("g.csv").exists() && out.join("g_pos_rmse_final_m.svg").exists());
    let bad = dir.join("bad.toml");
    std::fs::write(&bad, "name = \"b\"\nruns = 4\nfilters = [\"ekf\"]\nscenarios = [\"four-beacon-fusion\"]\n[variations]\nbeacons = [9]\n").unwrap();
    let (code, _, err) = entrynav(&[
        "trade",
        "--grid",
        bad.to_str().unwrap(),
        "--out-dir",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("variations.beacons = 9"), "{err}");
}

#[test]
fn optimize_orbiters_beats_the_paper_and_writes_a_usable_scenario() {
    let dir = tmpdir("optimize");
    let json = dir.join("o.json");
    let sc = dir.join("opt.toml");
    let (code, _, err) = entrynav(&[
        "optimize",
        "orbiters",
        "--scenario",
        "orbiters-3",
        "--objective",
        "det-n3",
        "--no-check",
        "--seed",
        "2",
        "--quiet",
        "--json",
        json.to_str().unwrap(),
        "--write-scenario",
        sc.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    for key in [
        "problem",
        "objective",
        "value",
        "elements",
        "evaluations",
        "elapsed_s",
    ] {
        assert!(v.get(key).is_some(), "optimize JSON lacks {key}: {v}");
    }
    assert!(
        v["value"].as_f64().unwrap() >= 237.963,
        "seed 002 Table 6 reaches 237.963: {}",
        v["value"]
    );
    assert_eq!(v["elements"].as_array().unwrap().len(), 3);
    let (code, out, err) = entrynav(&[
        "trade",
        "--scenario",
        sc.to_str().unwrap(),
        "--filters",
        "ekf",
        "--runs",
        "3",
        "--quiet",
    ]);
    assert_eq!(code, 0, "written scenario must run: {err}");
    assert!(out.contains("filter ekf"));
    let (code, _, err) = entrynav(&[
        "optimize",
        "orbiters",
        "--scenario",
        "orbiters-3",
        "--altitude-km",
        "-5",
        "--quiet",
    ]);
    assert_eq!(code, 2);
    assert!(err.contains("altitude"), "{err}");
}

fn gram(name: &str) -> String {
    format!(
        "{}/../core/tests/data/gram/{name}",
        env!("CARGO_MANIFEST_DIR")
    )
}

fn files_of(dir: &std::path::Path) -> Vec<(String, String)> {
    let mut out: Vec<(String, String)> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| {
            let p = e.unwrap().path();
            let name = p.file_name().unwrap().to_string_lossy().into_owned();
            (name, std::fs::read_to_string(&p).unwrap())
        })
        .collect();
    out.sort();
    out
}

#[test]
fn trade_over_a_gram_profile_set_flies_profile_k_mod_n() {
    let dir = tmpdir("gram-set");
    let set = gram("montecarlo-2.txt");
    let trade = |extra: &[&str], json: &std::path::Path| {
        let mut args = vec![
            "trade",
            "--scenario",
            "msl-airdata",
            "--filters",
            "ekf",
            "--runs",
            "4",
            "--seed",
            "7",
            "--quiet",
            "--no-pcrlb",
            "--atmosphere-file",
            &set,
            "--json",
        ];
        let json = json.to_str().unwrap().to_string();
        args.push(&json);
        args.extend_from_slice(extra);
        let (code, _, err) = entrynav(&args);
        assert_eq!(code, 0, "{err}");
        let v: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
        (v, err)
    };
    let (all, err) = trade(&[], &dir.join("set.json"));
    assert!(
        err.contains("holds 2 profiles: run k flies profile k mod 2"),
        "{err}"
    );
    let atm = &all["atmosphere"];
    assert_eq!(atm["profiles"], 2);
    assert!(atm["profile"].is_null());
    assert_eq!(atm["rule"], "run k flies profile k mod 2");
    assert!(atm["file"].as_str().unwrap().ends_with("montecarlo-2.txt"));
    assert!(atm["heights"].as_str().unwrap().contains("Radius"));
    let (one, _) = trade(&["--atmosphere-profile", "1"], &dir.join("one.json"));
    assert_eq!(one["atmosphere"]["profile"], 1);
    assert_eq!(one["atmosphere"]["rule"], "every run flies profile 1 of 2");
    assert_ne!(
        all["filters"][0]["rmse_time_avg"], one["filters"][0]["rmse_time_avg"],
        "cycling and profile-1-only studies should differ"
    );
    // Run 1 of the set is run 1 flown in profile 1, not in profile 0; run 0 is profile 0's.
    let replay = |run: &str, extra: &[&str], name: &str| {
        let out = dir.join(name);
        let mut args = vec![
            "trade",
            "--scenario",
            "msl-airdata",
            "--filters",
            "ekf",
            "--runs",
            "4",
            "--seed",
            "7",
            "--quiet",
            "--atmosphere-file",
            &set,
            "--replay-run",
            run,
            "--csv-dir",
        ];
        let out_s = out.to_str().unwrap().to_string();
        args.push(&out_s);
        args.extend_from_slice(extra);
        let (code, _, err) = entrynav(&args);
        assert_eq!(code, 0, "{err}");
        files_of(&out)
    };
    let set_run1 = replay("1", &[], "r1-set");
    assert!(!set_run1.is_empty());
    assert_eq!(
        set_run1,
        replay("1", &["--atmosphere-profile", "1"], "r1-p1")
    );
    assert_ne!(
        set_run1,
        replay("1", &["--atmosphere-profile", "0"], "r1-p0")
    );
    assert_eq!(
        replay("0", &[], "r0-set"),
        replay("0", &["--atmosphere-profile", "0"], "r0-p0")
    );
    // Out of range.
    let (code, _, err) = entrynav(&[
        "trade",
        "--scenario",
        "msl-airdata",
        "--runs",
        "1",
        "--quiet",
        "--atmosphere-file",
        &set,
        "--atmosphere-profile",
        "2",
    ]);
    assert_eq!(code, 2);
    assert!(
        err.contains("atmosphere_profile = 2 is out of range: must be from 0 to 1")
            && err.contains("montecarlo-2.txt"),
        "{err}"
    );
}

#[test]
fn atmosphere_inspect_reports_profiles_datum_coverage_and_plots() {
    let dir = tmpdir("inspect");
    let svg = dir.join("p.svg");
    let (code, out, err) = entrynav(&[
        "atmosphere",
        "inspect",
        &gram("montecarlo-3.txt"),
        "--svg",
        svg.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("profiles  3") && out.contains("Var_X") && out.contains("DENSTOT"),
        "{out}"
    );
    assert!(out.contains("radius column Radius"), "{out}");
    assert!(out.contains("covered by 3 of 3 profile(s)"), "{out}");
    let text = std::fs::read_to_string(&svg).unwrap();
    assert!(text.contains("<svg") && text.contains("profile 2") && text.contains("onboard model"));
    // No radius column, no datum: a warning; with the datum, none.
    let (code, out, err) = entrynav(&["atmosphere", "inspect", &gram("hgtmola.txt")]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("warning") && err.contains("no radius column and no datum"),
        "{err}"
    );
    assert!(out.contains("assumed"), "{out}");
    let (code, out, err) = entrynav(&[
        "atmosphere",
        "inspect",
        &gram("hgtmola.txt"),
        "--atmosphere-datum",
        "areoid",
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        !err.contains("warning") && out.contains("above the areoid"),
        "{err}\n{out}"
    );
    // A bad file names file, line and problem.
    let bad = dir.join("bad.txt");
    let text = std::fs::read_to_string(gram("averaged.txt")).unwrap();
    std::fs::write(&bad, text.replacen("3390.419", "3390.4x9", 1)).unwrap();
    let (code, _, err) = entrynav(&["atmosphere", "inspect", bad.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(
        err.contains("bad.txt: line 2") && err.contains("is not a number"),
        "{err}"
    );
}

/// A trade JSON without its `timing` block (and, when asked, without the command line).
fn reproducible_part(path: &std::path::Path, drop_command_line: bool) -> serde_json::Value {
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let obj = v.as_object_mut().unwrap();
    assert!(obj.remove("timing").is_some(), "no timing block");
    if drop_command_line {
        obj["provenance"]
            .as_object_mut()
            .unwrap()
            .remove("command_line");
    }
    v
}

#[test]
fn trade_json_has_provenance_and_is_identical_across_threads_and_repeats() {
    let dir = tmpdir("provenance");
    let run = |threads: &str, name: &str| {
        let path = dir.join(name);
        let (code, _, err) = entrynav(&[
            "trade",
            "--scenario",
            "orbiters-3",
            "--filters",
            "ekf,ukf",
            "--runs",
            "5",
            "--seed",
            "4",
            "--set",
            "truth.density_bias=0.05",
            "--threads",
            threads,
            "--quiet",
            "--json",
            path.to_str().unwrap(),
        ]);
        assert_eq!(code, 0, "{err}");
        path
    };
    let text = |p: &std::path::Path| std::fs::read_to_string(p).unwrap();
    let strip_timing = |t: String| t[..t.find("\"timing\"").expect("timing block")].to_string();
    // The same command twice: everything but `timing` byte-identical.
    let a = run("1", "a.json");
    let first = text(&a);
    run("1", "a.json");
    let second = text(&a);
    assert!(strip_timing(first.clone()) == strip_timing(second.clone()));
    assert!(first != second, "timing should be measured, not constant");
    // One thread against two: identical but for the command line.
    let c = run("2", "c.json");
    assert!(reproducible_part(&a, true) == reproducible_part(&c, true));

    let v: serde_json::Value = serde_json::from_str(&text(&a)).unwrap();
    let p = &v["provenance"];
    assert_eq!(p["version"], env!("CARGO_PKG_VERSION"));
    assert!(p["git_commit"].is_null() || p["git_commit"].as_str().unwrap().len() == 40);
    assert_eq!(
        p["overrides"],
        serde_json::json!(["truth.density_bias=0.05"])
    );
    let cmd: Vec<&str> = p["command_line"]
        .as_array()
        .unwrap()
        .iter()
        .map(|s| s.as_str().unwrap())
        .collect();
    assert!(cmd.windows(2).any(|w| w == ["--threads", "1"]), "{cmd:?}");
    let fp = p["scenario_fingerprint"].as_str().unwrap();
    assert_eq!(fp.len(), 16);
    assert!(p["atmosphere"]["truth"].is_object(), "{p}");
    // The override changes the fingerprint.
    let d = dir.join("d.json");
    let (code, _, err) = entrynav(&[
        "trade",
        "--scenario",
        "orbiters-3",
        "--runs",
        "2",
        "--quiet",
        "--json",
        d.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let vd: serde_json::Value = serde_json::from_str(&text(&d)).unwrap();
    assert_ne!(
        vd["provenance"]["scenario_fingerprint"].as_str().unwrap(),
        fp
    );
    // Timing lives only in `timing`.
    for f in v["filters"].as_array().unwrap() {
        assert!(f.get("us_per_step").is_none(), "{f}");
    }
    assert!(v["timing"]["us_per_step"]["ekf"].as_f64().unwrap() > 0.0);
}

#[test]
fn sigint_writes_the_partial_summary_of_the_completed_runs_and_exits_130() {
    let dir = tmpdir("sigint");
    let json = dir.join("partial.json");
    let common = [
        "trade",
        "--scenario",
        "orbiters-3",
        "--filters",
        "ekf",
        "--seed",
        "8",
        "--threads",
        "1",
    ];
    let args: Vec<&str> = common
        .iter()
        .copied()
        .chain(["--runs", "1000000", "--json", json.to_str().unwrap()])
        .collect();
    let mut child = common::spawn_with_progress(&args, std::process::Stdio::null());
    // Interrupt once runs have finished (no sleep: the progress line says so).
    let first = child.wait_for_runs(0);
    child.interrupt();
    let end = child.finish(60);
    let err = &end.err;
    assert_eq!(end.status.code(), Some(130), "{err}");
    assert!(err.contains("interrupted"), "{err}");
    let partial: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    assert_eq!(partial["complete"], false);
    assert_eq!(partial["runs"], 1000000);
    let done = partial["runs_completed"].as_u64().unwrap();
    // Every run reported finished is in the summary, and nothing else: the last progress line
    // (written after the runs cut short by Ctrl-C were folded) is the summary's count.
    assert!(done >= first && done < 1000000, "{done} after {first}");
    assert_eq!(end.last_progress, Some(done), "{err}");
    assert_eq!(partial["filters"][0]["runs"], done);

    // The partial statistics are exactly those of a study of `done` runs.
    let full_json = dir.join("full.json");
    let (code, _, err) = entrynav(
        &[
            &common[..],
            &[
                "--quiet",
                "--runs",
                &done.to_string(),
                "--json",
                full_json.to_str().unwrap(),
            ],
        ]
        .concat(),
    );
    assert_eq!(code, 0, "{err}");
    let full: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&full_json).unwrap()).unwrap();
    assert_eq!(full["complete"], true);
    assert!(partial["filters"] == full["filters"], "partial != full");
    assert!(partial["pcrlb"] == full["pcrlb"], "partial PCRLB != full");
}

#[test]
fn a_second_sigint_kills_a_study_that_is_writing_its_partial_results() {
    use std::os::unix::process::ExitStatusExt;
    // The summary goes to a pipe nobody reads: three filters' series are far more than a pipe
    // holds (64 KiB), so after the first Ctrl-C the process stays in that write until killed.
    let mut child = common::spawn_with_progress(
        &[
            "trade",
            "--scenario",
            "four-beacon-fusion",
            "--filters",
            "ekf,dcifaif,ukf",
            "--threads",
            "1",
            "--runs",
            "1000000",
            "--json",
            "-",
        ],
        std::process::Stdio::piped(),
    );
    child.wait_for_runs(0);
    child.interrupt();
    child.wait_for_line(|l| l.starts_with("interrupted: "));
    child.interrupt();
    let end = child.finish(60);
    assert_eq!(
        end.status.signal(),
        Some(2),
        "not killed by SIGINT: {:?}",
        end.status
    );
}

#[test]
fn output_paths_are_checked_before_the_first_run() {
    let dir = tmpdir("outputs");
    let file = dir.join("a-file");
    std::fs::write(&file, "x").unwrap();
    let bad = file.join("sub").join("t.json");
    let clock = std::time::Instant::now();
    let (code, _, err) = entrynav(&[
        "trade",
        "--scenario",
        "orbiters-3",
        "--runs",
        "1000000",
        "--quiet",
        "--json",
        bad.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains(bad.to_str().unwrap()), "{err}");
    assert!(clock.elapsed().as_secs() < 20, "ran the study first");
    let (code, _, err) = entrynav(&[
        "trade",
        "--scenario",
        "orbiters-3",
        "--runs",
        "1000000",
        "--csv-dir",
        file.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("--csv-dir") && err.contains("a-file"), "{err}");
}

#[test]
fn json_dash_writes_the_summary_to_stdout_only() {
    let (code, out, err) = entrynav(&[
        "trade",
        "--scenario",
        "orbiters-3",
        "--runs",
        "2",
        "--quiet",
        "--json",
        "-",
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value = serde_json::from_str(&out).expect("stdout is one JSON document");
    assert_eq!(v["runs"], 2);
    assert!(v["provenance"]["scenario_fingerprint"].is_string());
    assert!(!std::path::Path::new("-").exists());
}

#[test]
fn usage_errors_exit_2_with_a_clear_message() {
    let (code, _, err) = entrynav(&["trade", "--scenario", "orbiters-3", "--threads", "0"]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("1 to 1024"), "{err}");
    let (code, _, err) = entrynav(&["trade", "--scenario", "no-such-scenario"]);
    assert_eq!(code, 2, "{err}");
    let (code, _, err) = entrynav(&["trade", "--scenario", "orbiters-3", "--filters", "nope"]);
    assert_eq!(code, 2, "{err}");
}

#[test]
fn simulate_into_a_closed_pipe_ends_quietly_and_names_the_stop_reason() {
    use std::io::BufRead;
    // Far more CSV than a pipe buffers (64 KiB), so the writer meets the closed pipe.
    let (code, csv, err) = entrynav(&["simulate", "--scenario", "msl-airdata", "--out", "-"]);
    assert_eq!(code, 0, "{err}");
    assert!(csv.len() > 1 << 18, "only {} bytes", csv.len());
    assert!(csv.starts_with("t_s,"), "{}", &csv[..80]);
    let mut child = Command::new(env!("CARGO_BIN_EXE_entrynav"))
        .args(["simulate", "--scenario", "msl-airdata", "--out", "-"])
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let mut first = String::new();
    std::io::BufReader::new(child.stdout.take().unwrap())
        .read_line(&mut first)
        .unwrap(); // the reader is dropped here: the pipe closes after one line
    let out = child.wait_with_output().unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert!(err.trim().is_empty(), "not quiet on a closed pipe: {err}");
    assert_ne!(out.status.code(), Some(101), "{err}");
    let (code, out, err) = entrynav(&["simulate", "--scenario", "orbiters-3"]);
    assert_eq!(code, 0, "{err}");
    let stop = out.lines().find(|l| l.starts_with("stopped")).unwrap();
    for debug in ["(Duration)", "(StopSpeed)", "(Ground)"] {
        assert!(!stop.contains(debug), "{stop}");
    }
}

#[test]
fn final_errors_csv_has_one_row_per_run_and_filter_matching_the_summary() {
    let dir = tmpdir("finals");
    let json = dir.join("t.json");
    let csv = dir.join("csv");
    let (code, _, err) = entrynav(&[
        "trade",
        "--scenario",
        "four-beacon-fusion-fault",
        "--filters",
        "ekf,dcifaif",
        "--runs",
        "7",
        "--seed",
        "2",
        "--quiet",
        "--json",
        json.to_str().unwrap(),
        "--csv-dir",
        csv.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&json).unwrap()).unwrap();
    let (header, rows) = read_csv(&csv.join("four-beacon-fusion-fault_final_errors.csv"));
    assert_eq!(&header[..4], ["run", "filter", "status", "err_r_m"]);
    assert_eq!(&header[header.len() - 3..], ["pos_m", "vel_mps", "nees"]);
    assert_eq!(rows.len(), 14, "7 runs x 2 filters");
    for f in v["filters"].as_array().unwrap() {
        let name = f["name"].as_str().unwrap();
        let mine: Vec<&Vec<String>> = rows.iter().filter(|r| r[1] == name).collect();
        let runs: Vec<usize> = mine.iter().map(|r| r[0].parse().unwrap()).collect();
        assert_eq!(runs, (0..7).collect::<Vec<_>>());
        let count = |s: &str| mine.iter().filter(|r| r[2] == s).count() as u64;
        assert_eq!(count("failed"), f["failed"].as_u64().unwrap());
        assert_eq!(count("diverged"), f["diverged"].as_u64().unwrap());
        // The RMS of the completed runs' final position errors is the summary's rmse_final.
        let pos: Vec<f64> = mine
            .iter()
            .filter(|r| r[2] != "failed")
            .map(|r| r[header.len() - 3].parse().unwrap())
            .collect();
        let rms = (pos.iter().map(|x| x * x).sum::<f64>() / pos.len() as f64).sqrt();
        let want = f["rmse_final"]["pos_m"].as_f64().unwrap();
        assert!((rms - want).abs() <= 1e-9 * want, "{name}: {rms} vs {want}");
    }
}

#[test]
fn resume_continues_an_interrupted_study_to_exactly_the_uninterrupted_result() {
    // A study too long to finish is interrupted, resumed and interrupted again: the second
    // partial summary (its own runs plus the first one's) equals an uninterrupted study of as
    // many runs. Each interruption waits for a progress line, so no timing is involved.
    let dir = tmpdir("resume");
    let first = dir.join("first.json");
    let second = dir.join("second.json");
    let common = [
        "trade",
        "--scenario",
        "orbiters-3",
        "--filters",
        "ekf",
        "--seed",
        "11",
        "--threads",
        "1",
    ];
    let interrupted = |extra: &[&str], out: &std::path::Path, after: u64| -> serde_json::Value {
        let args: Vec<&str> = common
            .iter()
            .copied()
            .chain(["--runs", "1000000"])
            .chain(extra.iter().copied())
            .chain(["--json", out.to_str().unwrap()])
            .collect();
        let mut child = common::spawn_with_progress(&args, std::process::Stdio::null());
        child.wait_for_runs(after);
        child.interrupt();
        let end = child.finish(60);
        assert_eq!(end.status.code(), Some(130), "{}", end.err);
        let p: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out).unwrap()).unwrap();
        assert_eq!(p["complete"], false);
        assert!(p["resume"].is_object());
        assert_eq!(end.last_progress, p["runs_completed"].as_u64());
        p
    };
    let p1 = interrupted(&[], &first, 0);
    let k1 = p1["runs_completed"].as_u64().unwrap();
    let p2 = interrupted(&["--resume", first.to_str().unwrap()], &second, k1);
    let k2 = p2["runs_completed"].as_u64().unwrap();
    assert!(k1 > 0 && k2 > k1, "{k1} then {k2}");

    let full = dir.join("full.json");
    let k2_runs = k2.to_string();
    let args: Vec<&str> = common
        .iter()
        .copied()
        .chain([
            "--quiet",
            "--runs",
            &k2_runs,
            "--json",
            full.to_str().unwrap(),
        ])
        .collect();
    let (code, _, err) = entrynav(&args);
    assert_eq!(code, 0, "{err}");
    let f: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&full).unwrap()).unwrap();
    assert_eq!(f["complete"], true);
    assert!(f.get("resume").is_none());
    assert!(p2["filters"] == f["filters"], "resumed != uninterrupted");
    assert!(p2["pcrlb"] == f["pcrlb"], "resumed PCRLB != uninterrupted");
    // Resuming with another seed is refused.
    let mut other: Vec<&str> = common.to_vec();
    other[6] = "12";
    other.extend(["--runs", "1000000", "--resume", first.to_str().unwrap()]);
    let (code, _, err) = entrynav(&other);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("seed"), "{err}");
}

#[test]
fn an_interrupted_grid_keeps_the_cells_it_finished() {
    let dir = tmpdir("grid-sigint");
    let grid = dir.join("g.toml");
    std::fs::write(
        &grid,
        "name = \"g\"\nruns = 300\nfilters = [\"ekf\"]\nscenarios = [\"orbiters-3\"]\n[variations]\nnoise_scale = [1.0, 1.5, 2.0, 2.5, 3.0, 3.5, 4.0, 4.5, 5.0, 5.5]\n",
    )
    .unwrap();
    let out = dir.join("out");
    let report = out.join("g.json");
    let mut child = Command::new(env!("CARGO_BIN_EXE_entrynav"))
        .args(["trade", "--grid", grid.to_str().unwrap(), "--out-dir"])
        .arg(&out)
        .args(["--quiet"])
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    // Wait for the first cell's report, then interrupt.
    let clock = std::time::Instant::now();
    while std::fs::read_to_string(&report)
        .ok()
        .is_none_or(|t| serde_json::from_str::<serde_json::Value>(&t).is_err())
    {
        assert!(clock.elapsed().as_secs() < 300, "no cell finished");
        std::thread::sleep(std::time::Duration::from_millis(20));
    }
    Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert_eq!(child.wait().unwrap().code(), Some(130));
    let v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&report).unwrap()).unwrap();
    let cells = v["reports"].as_array().unwrap().len();
    assert!((1..10).contains(&cells), "{cells} cells");
    assert_eq!(v["cells"].as_array().unwrap().len(), cells);
    assert!(v["provenance"]["version"].is_string());
}

/// Read a CSV file whole; a row whose field count differs from the header's is an error.
fn read_csv(path: &std::path::Path) -> (Vec<String>, Vec<Vec<String>>) {
    let mut r = csv::ReaderBuilder::new()
        .comment(Some(b'#'))
        .from_path(path)
        .unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let header = r.headers().unwrap().iter().map(String::from).collect();
    let rows = r
        .records()
        .map(|rec| {
            rec.unwrap_or_else(|e| panic!("{}: {e}", path.display()))
                .iter()
                .map(String::from)
                .collect()
        })
        .collect();
    (header, rows)
}

#[test]
fn names_with_commas_stay_one_csv_field_in_every_csv_written() {
    let dir = tmpdir("commas");
    let (code, text, err) = entrynav(&["scenario", "show", "four-beacon-fusion"]);
    assert_eq!(code, 0, "{err}");
    let text = text
        .replacen(
            "name = \"four-beacon-fusion\"",
            "name = \"fusion, renamed\"",
            1,
        )
        .replacen("name = \"surface-1\"", "name = \"surface-1, Gale\"", 1);
    let scenario = dir.join("comma.toml");
    std::fs::write(&scenario, text).unwrap();
    let scenario = scenario.to_str().unwrap();

    let sim = dir.join("sim.csv");
    let (code, _, err) = entrynav(&[
        "simulate",
        "--scenario",
        scenario,
        "--out",
        sim.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let (header, rows) = read_csv(&sim);
    assert!(
        header.iter().any(|h| h == "visible_surface-1, Gale"),
        "{header:?}"
    );
    assert!(
        header.iter().any(|h| h == "range_surface-1, Gale_m"),
        "{header:?}"
    );
    assert!(rows.len() > 100);

    let replay = dir.join("replay");
    let (code, _, err) = entrynav(&[
        "trade",
        "--scenario",
        scenario,
        "--filters",
        "dcifaif",
        "--replay-run",
        "0",
        "--csv-dir",
        replay.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let (header, rows) = read_csv(&replay.join("fusion, renamed_run0_dcifaif.csv"));
    assert!(
        header.iter().any(|h| h == "weight_surface-1, Gale"),
        "{header:?}"
    );
    assert!(!rows.is_empty());

    let grid = dir.join("g.toml");
    std::fs::write(
        &grid,
        "name = \"g\"\nruns = 2\nfilters = [\"ekf\"]\nscenarios = [\"comma.toml\"]\n",
    )
    .unwrap();
    let out = dir.join("out");
    let (code, _, err) = entrynav(&[
        "trade",
        "--grid",
        grid.to_str().unwrap(),
        "--out-dir",
        out.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    let (header, rows) = read_csv(&out.join("g.csv"));
    let col = header.iter().position(|h| h == "scenario").unwrap();
    assert_eq!(rows.len(), 1);
    assert_eq!(rows[0][col], "fusion, renamed");
}

#[test]
fn a_file_that_cannot_be_read_is_named_with_the_reason() {
    let dir = tmpdir("unreadable");
    let missing = dir.join("missing.toml");
    let (code, _, err) = entrynav(&["scenario", "show", missing.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains(missing.to_str().unwrap()) && err.contains("No such file"),
        "{err}"
    );
    let missing = dir.join("missing.json");
    let (code, _, err) = entrynav(&[
        "trade",
        "--scenario",
        "orbiters-3",
        "--runs",
        "2",
        "--quiet",
        "--resume",
        missing.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains(&format!("--resume {}: cannot read", missing.display()))
            && err.contains("No such file"),
        "{err}"
    );
}

#[test]
fn run_counts_are_checked_by_value_negative_included() {
    for (flag, cmd) in [
        ("--runs", "trade"),
        ("--validation-runs", "tune"),
        ("--runs", "observe"),
    ] {
        for bad in ["-5", "0", "10000001", "1e3"] {
            let mut args = vec![cmd, "--scenario", "orbiters-3", flag, bad];
            if cmd == "tune" {
                args.extend(["--out", "/nonexistent/never.toml"]);
            }
            let (code, _, err) = common::entrynav(&args);
            assert_eq!(code, 2, "{cmd} {flag} {bad}: {err}");
            assert!(
                err.contains(&format!("invalid value '{bad}' for '{flag}"))
                    && err.contains("1 to 10000000"),
                "{cmd} {flag} {bad}: {err}"
            );
        }
    }
}

#[test]
fn tune_accepts_filters_as_trade_does() {
    let dir = common::scratch_dir("cli", "tune_filters");
    let out = dir.join("t.toml");
    let (code, stdout, err) = common::entrynav(&[
        "tune",
        "--scenario",
        "orbiters-3",
        "--filters",
        "ekf,ukf",
        "--runs",
        "4",
        "--validation-runs",
        "4",
        "--max-evaluations",
        "10",
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(stdout.contains("tuned ekf,ukf on orbiters-3"), "{stdout}");
}

#[test]
fn a_bad_set_is_blamed_on_its_argument_not_a_line_of_a_generated_document() {
    for (set, why) in [
        ("truth.initial.velocity_mps=abc", "expected a sequence"),
        ("timing.duration_s=\"x\"", "expected f64"),
        ("truth.bogus=1", "unknown field `bogus`"),
    ] {
        let (code, _, err) = entrynav(&[
            "trade",
            "--scenario",
            "orbiters-3",
            "--set",
            set,
            "--runs",
            "2",
        ]);
        assert_eq!(code, 2, "{set}: {err}");
        assert!(
            err.contains(&format!("--set '{set}'")) && err.contains(why),
            "{set}: {err}"
        );
        assert!(
            !err.contains("line ") && !err.contains("column"),
            "{set}: {err}"
        );
    }
}

#[test]
fn observe_fim_summarises_before_its_rows() {
    let (code, out, err) = entrynav(&["observe", "--scenario", "ground-beacons-3", "--fim"]);
    assert_eq!(code, 0, "{err}");
    let summary = out.find("summary over 241 epochs").expect("no summary");
    let first_row = out.find("\n    0.0   3 ").expect("no first row");
    assert!(summary < first_row, "the summary comes after the rows");
    assert!(out.contains("beacons in view 3..3") && out.contains("trF^-1 (bound on tr P) best"));
}
