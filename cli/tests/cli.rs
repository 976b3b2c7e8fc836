//! End-to-end tests of the `entrynav` binary.

use std::process::Command;

fn entrynav(args: &[&str]) -> (i32, String, String) {
    let out = Command::new(env!("CARGO_BIN_EXE_entrynav"))
        .args(args)
        .output()
        .expect("run entrynav");
    (
        out.status.code().unwrap_or(-1),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

fn tmpdir(name: &str) -> std::path::PathBuf {
    let d = std::env::temp_dir().join(format!("entrynav-cli-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&d).unwrap();
    d
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
    let text = std::fs::read_to_string(&csv).unwrap();
    let header: Vec<&str> = text.lines().next().unwrap().split(',').collect();
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
        assert!(header.contains(&col), "missing column {col} in {header:?}");
    }
    let rows: Vec<Vec<f64>> = text
        .lines()
        .skip(1)
        .map(|l| {
            l.split(',')
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
