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
        err.contains("--filter 'kalman'") && err.contains("ekf"),
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
        "dcifaif",
    ]);
    assert_ne!(code, 0);
    assert!(
        err.contains("cannot analyse filter 'dcifaif'") && err.contains("covariance-intersection"),
        "{err}"
    );
    let (code, _, err) = entrynav(&["lincov", "--scenario", "orbiters-3", "--compare-mc", "0"]);
    assert_ne!(code, 0);
    assert!(err.contains("--compare-mc 0"), "{err}");
}
