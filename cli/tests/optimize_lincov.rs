//! `optimize ground|orbiters --objective lincov-*`: the bound's optimum polished on the EKF's
//! LinCov; what it reports is what `entrynav lincov` predicts on the scenario it writes.

mod common;

use common::{entrynav, scratch_dir};
use serde_json::Value;
use std::path::Path;

fn read_json(path: &Path) -> Value {
    let text = std::fs::read_to_string(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    serde_json::from_str(&text).unwrap()
}

/// The EKF's (time-averaged, final) position RMSE that `entrynav lincov` predicts on `scenario`.
fn lincov_of(scenario: &Path) -> (f64, f64) {
    let s = scenario.to_str().unwrap();
    let (code, out, err) = entrynav(&["lincov", "--scenario", s, "--json", "-"]);
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    let f = &v["lincov"]["filters"][0];
    (
        f["rmse_time_avg"]["pos_m"].as_f64().unwrap(),
        f["rmse_final"]["pos_m"].as_f64().unwrap(),
    )
}

fn close(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-6 * b.abs()
}

#[test]
fn ground_lincov_nav_is_no_worse_than_its_start_and_is_what_lincov_predicts() {
    let dir = scratch_dir("optimize-lincov", "ground");
    let (json, toml) = (dir.join("g.json"), dir.join("g.toml"));
    let (code, out, err) = entrynav(&[
        "optimize",
        "ground",
        "--scenario",
        "ground-beacons-3",
        "--objective",
        "lincov-nav",
        "--no-check",
        "--quiet",
        "--json",
        json.to_str().unwrap(),
        "--write-scenario",
        toml.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{out}\n{err}");
    assert!(
        out.contains("predicted ekf position RMSE, polished"),
        "{out}"
    );
    let v = read_json(&json);
    assert_eq!(v["objective"], "lincov-nav");
    assert_eq!(v["search_objective"], "nav");
    let l = &v["lincov"];
    assert_eq!(l["filter"], "ekf");
    let fig = |k: &str, f: &str| l[k][f].as_f64().unwrap();
    let nav = |k: &str| {
        0.5 * (fig(k, "time_avg_pos_m") / fig("input", "time_avg_pos_m")
            + fig(k, "final_pos_m") / fig("input", "final_pos_m"))
    };
    // The value is the objective of the polished design, never worse than where it started.
    assert!(close(l["value"].as_f64().unwrap(), nav("optimum")), "{l}");
    assert!(nav("optimum") <= nav("bound_optimum") + 1e-12, "{l}");
    // Better than the hand-placed sites on both predicted figures.
    for f in ["time_avg_pos_m", "final_pos_m"] {
        assert!(fig("optimum", f) < fig("input", f), "{f}: {l}");
    }
    // What it reports is what `entrynav lincov` predicts on the written scenario and the input.
    let (avg, last) = lincov_of(&toml);
    assert!(close(avg, fig("optimum", "time_avg_pos_m")), "{avg} vs {l}");
    assert!(close(last, fig("optimum", "final_pos_m")), "{last} vs {l}");
    let (avg, last) = lincov_of(Path::new("ground-beacons-3"));
    assert!(close(avg, fig("input", "time_avg_pos_m")), "{avg} vs {l}");
    assert!(close(last, fig("input", "final_pos_m")), "{last} vs {l}");
}

#[test]
fn a_filter_lincov_cannot_analyse_is_refused_with_the_reason() {
    let (code, _out, err) = entrynav(&[
        "optimize",
        "ground",
        "--scenario",
        "ground-beacons-3",
        "--objective",
        "lincov-avg",
        "--lincov-filter",
        "mmae",
        "--no-check",
        "--quiet",
    ]);
    assert_ne!(code, 0);
    assert!(
        err.contains("lincov-avg") && err.contains("mmae") && err.contains("innovations"),
        "{err}"
    );
}

#[test]
fn orbiters_lincov_final_polishes_the_bound_optimum() {
    let dir = scratch_dir("optimize-lincov", "orbiters");
    let (json, toml) = (dir.join("o.json"), dir.join("o.toml"));
    let (code, out, err) = entrynav(&[
        "optimize",
        "orbiters",
        "--scenario",
        "orbiters-3",
        "--objective",
        "lincov-final",
        "--starts",
        "2",
        "--particles",
        "20",
        "--iterations",
        "40",
        "--no-check",
        "--quiet",
        "--json",
        json.to_str().unwrap(),
        "--write-scenario",
        toml.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{out}\n{err}");
    let v = read_json(&json);
    assert_eq!(v["objective"], "lincov-final");
    let l = &v["lincov"];
    let fig = |k: &str, f: &str| l[k][f].as_f64().unwrap();
    assert!(fig("optimum", "final_pos_m") <= fig("bound_optimum", "final_pos_m") + 1e-12);
    assert!(
        fig("optimum", "final_pos_m") < fig("input", "final_pos_m"),
        "{l}"
    );
    let (_, last) = lincov_of(&toml);
    assert!(close(last, fig("optimum", "final_pos_m")), "{last} vs {l}");
}

#[test]
fn select_lincov_final_exchanges_from_the_bound_selection() {
    let dir = scratch_dir("optimize-lincov", "select");
    let (json, toml) = (dir.join("s.json"), dir.join("s.toml"));
    let (code, out, err) = entrynav(&[
        "optimize",
        "select",
        "--scenario",
        "ground-beacons-3",
        "--k",
        "3",
        "--grid-deg",
        "1.0",
        "--objective",
        "lincov-final",
        "--no-check",
        "--quiet",
        "--json",
        json.to_str().unwrap(),
        "--write-scenario",
        toml.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{out}\n{err}");
    let v = read_json(&json);
    assert_eq!(v["objective"], "lincov-final");
    let l = &v["lincov"];
    let fig = |k: &str| l[k]["final_pos_m"].as_f64().unwrap();
    assert!(fig("optimum") <= fig("bound_selection") + 1e-12, "{l}");
    assert!(close(l["value"].as_f64().unwrap(), fig("optimum")), "{l}");
    assert!(l["evaluations"].as_u64().unwrap() > 1);
    let (_, last) = lincov_of(&toml);
    assert!(close(last, fig("optimum")), "{last} vs {l}");
}
