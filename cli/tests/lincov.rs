//! `entrynav lincov`: its prediction against a trade of the same filter, its files, and its
//! refusals.

mod common;

use common::{entrynav, scratch_dir};
use serde_json::Value;

fn json(out: &str) -> Value {
    serde_json::from_str(out).unwrap_or_else(|e| panic!("not JSON ({e}): {out}"))
}

#[test]
fn lincov_predicts_the_rmse_of_a_trade_of_the_same_filter() {
    let (code, out, err) = entrynav(&["lincov", "--scenario", "four-beacon-fusion", "--json", "-"]);
    assert_eq!(code, 0, "{err}");
    let l = json(&out);
    let f = &l["lincov"]["filters"][0];
    assert_eq!(f["name"], "ekf");
    let (code, out, err) = entrynav(&[
        "trade",
        "--scenario",
        "four-beacon-fusion",
        "--filters",
        "ekf",
        "--runs",
        "200",
        "--threads",
        "2",
        "--quiet",
        "--json",
        "-",
    ]);
    assert_eq!(code, 0, "{err}");
    let mc = json(&out);
    let m = &mc["filters"][0];
    for block in ["rmse_time_avg", "rmse_final"] {
        for key in ["pos_m", "vel_mps"] {
            let (a, b) = (
                f[block][key].as_f64().unwrap(),
                m[block][key].as_f64().unwrap(),
            );
            assert!(
                (a / b - 1.0).abs() < 0.15,
                "{block}.{key}: LinCov {a}, Monte Carlo {b}"
            );
        }
    }
    assert_eq!(f["nees_dof"], m["nees_dof"]);
    let ratio = |v: &Value| v["anees"].as_f64().unwrap() / v["nees_dof"].as_f64().unwrap();
    assert!(
        (ratio(f) / ratio(m) - 1.0).abs() < 0.2,
        "{} vs {}",
        ratio(f),
        ratio(m)
    );
}

#[test]
fn table_and_csv_series() {
    let dir = scratch_dir("lincov", "csv");
    let d = dir.to_str().unwrap();
    let (code, out, err) = entrynav(&["lincov", "--scenario", "orbiters-3", "--csv-dir", d]);
    assert_eq!(code, 0, "{err}");
    assert!(
        out.contains("pos RMSE [m]") && out.contains("NEES / dof"),
        "{out}"
    );
    let text = std::fs::read_to_string(dir.join("lincov_ekf.csv")).unwrap();
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap().split(',').collect();
    assert_eq!(&header[..3], &["t_s", "pos_rmse_m", "vel_rmse_mps"]);
    // orbiters-3: 240 s of 1 Hz ranges.
    let rows: Vec<Vec<f64>> = lines
        .map(|l| l.split(',').map(|v| v.parse().unwrap()).collect())
        .collect();
    assert_eq!(rows.len(), 240);
    assert!(rows.iter().all(|r| r[1] > 0.0 && r[1].is_finite()));
    std::fs::remove_dir_all(&dir).ok();
}

#[test]
fn a_bad_filter_name_is_refused_naming_the_option_and_the_choices() {
    let (code, _, err) = entrynav(&["lincov", "--scenario", "orbiters-3", "--filter", "kalman"]);
    assert_ne!(code, 0);
    assert!(
        err.contains("filters = 'kalman' is unknown") && err.contains("ekf"),
        "{err}"
    );
}

#[test]
fn a_filter_it_cannot_analyse_gets_the_reason() {
    let (code, _, err) = entrynav(&[
        "lincov",
        "--scenario",
        "four-beacon-fusion",
        "--filter",
        "ukf-cm",
    ]);
    assert_ne!(code, 0);
    assert!(
        err.contains("cannot analyse filter 'ukf-cm'")
            && err.contains("adapts its process noise")
            && err.contains("supported filters: ekf, ukf, ci, dcifaif"),
        "{err}"
    );
    let (code, _, err) = entrynav(&["lincov", "--scenario", "orbiters-3", "--compare-mc", "0"]);
    assert_ne!(code, 0);
    assert!(
        err.contains("compare_mc = 0 is out of range: must be from 1 to 20000"),
        "{err}"
    );
}

/// `trade --method both`: the summary carries LinCov beside the Monte Carlo with the ratio and
/// the Monte Carlo's interval for every headline figure; on a filter LinCov models well every
/// position figure is within 15 % and inside the interval.
#[test]
fn trade_method_both_puts_lincov_beside_the_monte_carlo() {
    let dir = scratch_dir("lincov", "trade-both");
    let json_path = dir.join("t.json");
    let (code, out, err) = entrynav(&[
        "trade",
        "--scenario",
        "orbiters-3",
        "--filters",
        "ekf",
        "--runs",
        "200",
        "--threads",
        "2",
        "--method",
        "both",
        "--quiet",
        "--json",
        json_path.to_str().unwrap(),
        "--plots",
        dir.join("plots").to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("LinCov beside the Monte Carlo"), "{out}");
    // The RMSE charts carry LinCov's curve beside the Monte Carlo's.
    let pos_chart = std::fs::read_dir(dir.join("plots"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .find(|p| p.to_string_lossy().contains("rmse_pos_m"))
        .expect("a position RMSE chart");
    let svg = std::fs::read_to_string(&pos_chart).unwrap();
    assert!(svg.contains("ekf LinCov"), "{}", pos_chart.display());
    let v = json(&std::fs::read_to_string(&json_path).unwrap());
    assert_eq!(v["runs"], 200);
    let l = &v["lincov"];
    assert_eq!(l["filters"][0]["name"], "ekf");
    let vs = &l["versus_monte_carlo"][0];
    assert_eq!(vs["name"], "ekf");
    let figures = vs["figures"].as_array().unwrap();
    let find = |name: &str| {
        figures
            .iter()
            .find(|f| f["figure"] == name)
            .unwrap_or_else(|| panic!("{name} missing: {vs}"))
    };
    for name in ["rmse_time_avg.pos_m", "rmse_final.pos_m"] {
        let f = find(name);
        let mc = f["monte_carlo"].as_f64().unwrap();
        assert_eq!(
            mc,
            v["filters"][0][name.split('.').next().unwrap()]["pos_m"]
        );
        let ratio = f["ratio"].as_f64().unwrap();
        assert!((ratio - 1.0).abs() < 0.15, "{f}");
        assert_eq!(f["outside_mc_interval"], false, "{f}");
    }
    assert!(find("anees_per_dof")["lincov"].as_f64().unwrap() > 0.0);
}

/// `trade --method both` with the fusion filters: LinCov of `ci` and `dcifaif` beside their
/// Monte Carlo; on four-beacon-fusion DCIFAIF's position RMSEs agree to 15 % (CI's local filters,
/// one range each from a 12 km start error, diverge in the Monte Carlo: docs/results.md).
#[test]
fn trade_method_both_analyses_the_fusion_filters() {
    let (code, out, err) = entrynav(&[
        "trade",
        "--scenario",
        "four-beacon-fusion",
        "--filters",
        "ci,dcifaif",
        "--runs",
        "100",
        "--threads",
        "2",
        "--method",
        "both",
        "--quiet",
        "--json",
        "-",
    ]);
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    let names: Vec<&Value> = v["lincov"]["filters"]
        .as_array()
        .unwrap()
        .iter()
        .map(|f| &f["name"])
        .collect();
    assert_eq!(names, ["ci", "dcifaif"]);
    let vs = v["lincov"]["versus_monte_carlo"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["name"] == "dcifaif")
        .unwrap();
    for name in ["rmse_time_avg.pos_m", "rmse_final.pos_m"] {
        let f = vs["figures"]
            .as_array()
            .unwrap()
            .iter()
            .find(|f| f["figure"] == name)
            .unwrap();
        let ratio = f["ratio"].as_f64().unwrap();
        assert!((ratio - 1.0).abs() < 0.15, "{f}");
    }
    // The filter's C_D S/m is 10 % off the truth's, so LinCov predicts a mean error (its NEES/dof
    // share is 0.062) and the Monte Carlo's agrees with it.
    let f = vs["figures"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["figure"] == "mean_error_nees_per_dof")
        .unwrap();
    assert!(f["lincov"].as_f64().unwrap() > 0.03, "{f}");
    assert_eq!(f["outside_mc_interval"], false, "{f}");
}

/// `trade --method lincov` is `entrynav lincov`; options with no meaning for it are refused.
#[test]
fn trade_method_lincov_is_the_lincov_command_and_refuses_monte_carlo_options() {
    let args = ["--scenario", "four-beacon-fusion", "--json", "-"];
    let (code, a, err) = entrynav(&[&["lincov"][..], &args[..]].concat());
    assert_eq!(code, 0, "{err}");
    let (code, b, err) = entrynav(&[&["trade", "--method", "lincov"][..], &args[..]].concat());
    assert_eq!(code, 0, "{err}");
    let strip = |s: &str| {
        let mut v = json(s);
        for f in v["lincov"]["filters"].as_array_mut().unwrap() {
            f["wall_s"] = Value::Null;
        }
        v
    };
    assert_eq!(strip(&a), strip(&b));
    for (extra, flag) in [
        (&["--runs", "10"][..], "--runs"),
        (&["--resume", "partial.json"][..], "--resume"),
        (&["--plots", "p"][..], "--plots"),
    ] {
        let (code, _, err) = entrynav(
            &[
                &[
                    "trade",
                    "--method",
                    "lincov",
                    "--scenario",
                    "four-beacon-fusion",
                ][..],
                extra,
            ]
            .concat(),
        );
        assert_eq!(code, 2, "{flag}: {err}");
        assert!(
            err.contains("--method lincov") && err.contains(flag),
            "{err}"
        );
    }
}

/// `trade --grid FILE --method lincov`: every cell by LinCov — the full-geometry, unit-noise cell
/// is exactly `entrynav lincov`'s prediction (the EKF's and the DCIFAIF fusion's), fewer beacons
/// and more noise predict more error, and a filter LinCov cannot analyse is a refused row naming
/// why.
#[test]
fn a_lincov_grid_predicts_every_cell() {
    let dir = scratch_dir("lincov", "grid");
    let grid = dir.join("g.toml");
    std::fs::write(
        &grid,
        "name = \"g\"\nruns = 1\nfilters = [\"ekf\", \"dcifaif\", \"ukf-cm\"]\nscenarios = [\"four-beacon-fusion\"]\n\
         [variations]\nbeacons = [2, 4]\nnoise_scale = [1.0, 2.0]\n",
    )
    .unwrap();
    let out_dir = dir.join("out");
    let (code, out, err) = entrynav(&[
        "trade",
        "--grid",
        grid.to_str().unwrap(),
        "--method",
        "lincov",
        "--out-dir",
        out_dir.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{out}\n{err}");
    let v = json(&std::fs::read_to_string(out_dir.join("g.json")).unwrap());
    assert_eq!(v["method"], "lincov");
    let cells = v["cells"].as_array().unwrap();
    let ekf: Vec<&Value> = cells.iter().filter(|c| c["filter"] == "ekf").collect();
    assert_eq!(ekf.len(), 4, "{cells:?}");
    let pos = |rows: &[&Value], beacons: &str, noise: &str| {
        rows.iter()
            .find(|c| {
                let var = c["variation"].as_str().unwrap();
                var.contains(&format!("{beacons} beacons"))
                    && var.contains(&format!("noise x{noise}"))
            })
            .unwrap_or_else(|| panic!("{beacons}/{noise}: {rows:?}"))["pos_rmse_avg_m"]
            .as_f64()
            .unwrap()
    };
    let dcifaif: Vec<&Value> = cells.iter().filter(|c| c["filter"] == "dcifaif").collect();
    assert_eq!(dcifaif.len(), 4, "{cells:?}");
    for (rows, filter) in [(&ekf, "ekf"), (&dcifaif, "dcifaif")] {
        let (code, l, err) = entrynav(&[
            "lincov",
            "--scenario",
            "four-beacon-fusion",
            "--filter",
            filter,
            "--json",
            "-",
        ]);
        assert_eq!(code, 0, "{err}");
        let direct = json(&l)["lincov"]["filters"][0]["rmse_time_avg"]["pos_m"]
            .as_f64()
            .unwrap();
        let full = pos(rows, "4", "1");
        assert!(
            (full / direct - 1.0).abs() < 1e-12,
            "{filter}: {full} vs {direct}"
        );
        assert!(pos(rows, "2", "1") > full, "{filter}");
        assert!(pos(rows, "4", "2") > full, "{filter}");
    }
    let refused: Vec<&Value> = cells.iter().filter(|c| c["filter"] == "ukf-cm").collect();
    assert!(!refused.is_empty());
    for r in refused {
        let why = r["refused"].as_str().unwrap_or_default();
        assert!(
            why.contains("LinCov") && why.contains("adapts its process noise"),
            "{r}"
        );
    }
}

/// `--compare-mc` splits off the NEES/dof a mean error carries. On orbiters-3 the CI locals'
/// drag, biased by their km-sized altitude errors, gives CI's Monte Carlo a mean error LinCov
/// does not predict (docs/results.md); DCIFAIF's feedback keeps its locals at the fused estimate
/// and its share stays at the sampling floor, (NEES/dof)/runs ≈ 0.005.
#[test]
fn compare_mc_shows_the_mean_error_lincov_does_not_predict() {
    let (code, out, err) = entrynav(&[
        "lincov",
        "--scenario",
        "orbiters-3",
        "--filter",
        "ci,dcifaif",
        "--compare-mc",
        "200",
        "--threads",
        "2",
        "--json",
        "-",
    ]);
    assert_eq!(code, 0, "{err}");
    let v = json(&out);
    let share = |block: &str, name: &str| {
        let f = v[block]["filters"]
            .as_array()
            .unwrap()
            .iter()
            .find(|f| f["name"] == name)
            .unwrap();
        f["mean_error_nees_ratio_time_avg"].as_f64().unwrap()
    };
    for name in ["ci", "dcifaif"] {
        let lc = share("lincov", name);
        assert!(lc < 1e-3, "{name}: LinCov's own mean error share {lc}");
    }
    let ci = share("monte_carlo", "ci");
    assert!(ci > 0.15, "ci: the Monte Carlo's mean-error share {ci}");
    let dcifaif = share("monte_carlo", "dcifaif");
    assert!(dcifaif < 0.02, "dcifaif: {dcifaif}");
}

/// `--second-order-mean` carries the CI locals' drag bias on orbiters-3 (NEES/dof 0.50 → 0.83,
/// the Monte Carlo's is 1.07) and says so in the notes; where CI's Monte Carlo diverges
/// (ground-beacons-3) it is refused naming the state, the epoch and the flag.
#[test]
fn second_order_mean_carries_the_bias_or_refuses() {
    let run = |extra: &[&str]| {
        let mut args = vec![
            "lincov",
            "--scenario",
            "orbiters-3",
            "--filter",
            "ci",
            "--json",
            "-",
        ];
        args.extend_from_slice(extra);
        let (code, out, err) = entrynav(&args);
        assert_eq!(code, 0, "{err}");
        json(&out)["lincov"]["filters"][0].clone()
    };
    let (first, second) = (run(&[]), run(&["--second-order-mean"]));
    let nees = |f: &Value| f["nees_ratio_time_avg"].as_f64().unwrap();
    let mean = |f: &Value| f["mean_error_nees_ratio_time_avg"].as_f64().unwrap();
    assert!(
        nees(&first) < 0.55 && nees(&second) > 0.75,
        "{first} {second}"
    );
    assert!(
        mean(&first) < 1e-3 && mean(&second) > 0.25,
        "{first} {second}"
    );
    let notes = second["notes"].to_string();
    assert!(notes.contains("second-order mean"), "{notes}");
    let (code, _, err) = entrynav(&[
        "lincov",
        "--scenario",
        "ground-beacons-3",
        "--filter",
        "ci",
        "--second-order-mean",
    ]);
    assert_ne!(code, 0);
    for part in [
        "second-order mean at t = ",
        "in state ",
        "--second-order-mean",
    ] {
        assert!(err.contains(part), "{part}: {err}");
    }
}
