//! End-to-end tests of `entrynav trade compare`.

mod common;
use common::entrynav;
use serde_json::Value;
use std::path::Path;

fn tmpdir(name: &str) -> std::path::PathBuf {
    common::scratch_dir("compare", name)
}

/// A 20-run trade summary of `scenario` with `filters` and `seed`, through plain
/// `entrynav trade --scenario …` (which must keep working beside `trade compare`).
fn summary(dir: &Path, name: &str, scenario: &str, filters: &str, seed: &str) -> String {
    let path = dir.join(name);
    let p = path.to_str().unwrap();
    let args = [
        "trade",
        "--scenario",
        scenario,
        "--filters",
        filters,
        "--runs",
        "20",
        "--seed",
        seed,
        "--no-pcrlb",
        "--quiet",
        "--json",
        p,
    ];
    let (code, out, err) = entrynav(&args);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("filter ekf"), "trade table missing:\n{out}");
    p.to_string()
}

fn compare_json(a: &str, b: &str, extra: &[&str]) -> Value {
    let mut args = vec!["trade", "compare", a, b, "--json", "-"];
    args.extend_from_slice(extra);
    let (code, out, err) = entrynav(&args);
    assert_eq!(code, 0, "{err}");
    serde_json::from_str(&out).expect("compare --json - writes JSON only")
}

fn rows<'a>(v: &'a Value, filter: &str) -> &'a Vec<Value> {
    v["filters"]
        .as_array()
        .unwrap()
        .iter()
        .find(|f| f["name"] == filter)
        .unwrap_or_else(|| panic!("{filter} not compared"))["rows"]
        .as_array()
        .unwrap()
}

#[test]
fn two_seeds_compare_per_filter_state_and_error_norm_with_intervals() {
    let dir = tmpdir("seeds");
    let a = summary(&dir, "a.json", "four-beacon-fusion", "ekf,ci", "1");
    let b = summary(&dir, "b.json", "four-beacon-fusion", "ekf,dcifaif", "2");
    let (code, table, err) = entrynav(&["trade", "compare", &a, &b]);
    assert_eq!(code, 0, "{err}");
    for needed in [
        "filter ekf",
        "rmse_time_avg",
        "rmse_final",
        "pos_m",
        "vel_mps",
        "anees",
    ] {
        assert!(table.contains(needed), "{needed} missing:\n{table}");
    }
    assert!(table.contains("independent runs"), "{table}");
    assert!(
        table.contains("RMSE/sqrt(2N)"),
        "the approximation is named:\n{table}"
    );
    let v = compare_json(&a, &b, &[]);
    assert_eq!(v["only_in_a"], serde_json::json!(["ci"]));
    assert_eq!(v["only_in_b"], serde_json::json!(["dcifaif"]));
    let ekf = rows(&v, "ekf");
    for metric in ["rmse_time_avg", "rmse_final"] {
        for state in ["pos_m", "vel_mps", "r_m", "v_mps"] {
            let r = ekf
                .iter()
                .find(|r| r["metric"] == metric && r["state"] == state)
                .unwrap_or_else(|| panic!("{metric} {state} missing"));
            let (va, vb) = (
                r["a"]["value"].as_f64().unwrap(),
                r["b"]["value"].as_f64().unwrap(),
            );
            let diff = r["diff"].as_f64().unwrap();
            assert!((diff - (vb - va)).abs() <= 1e-12 * va.abs().max(1.0));
            let (lo, hi) = (
                r["ci_low"].as_f64().unwrap(),
                r["ci_high"].as_f64().unwrap(),
            );
            assert!(lo < diff && diff < hi, "{r}");
            // The interval is about ±1.96·√2·RMSE/√40 wide at most: not degenerate, not huge.
            assert!(hi - lo > 0.0 && hi - lo < 2.0 * va.max(vb), "{r}");
            assert_eq!(r["significant"], Value::Bool(lo > 0.0 || hi < 0.0));
        }
    }
    let anees = ekf.iter().find(|r| r["metric"] == "anees").unwrap();
    assert_eq!(anees["band"]["dof"], 11);
    assert!(anees["band"]["a_inside"].is_boolean());
}

#[test]
fn identical_summaries_differ_by_zero_and_nothing_is_significant() {
    let dir = tmpdir("same");
    let a = summary(&dir, "a.json", "four-beacon-fusion", "ekf,ci", "3");
    let v = compare_json(&a, &a, &[]);
    let notes = v["notes"].to_string();
    assert!(notes.contains("same runs (paired)"), "{notes}");
    for f in v["filters"].as_array().unwrap() {
        for r in f["rows"].as_array().unwrap() {
            assert_eq!(r["diff"], 0.0, "{r}");
            assert_eq!(r["significant"], false, "{r}");
        }
    }
    assert_eq!(v["filters"].as_array().unwrap().len(), 2);
}

#[test]
fn different_scenarios_are_compared_and_their_differences_listed() {
    let dir = tmpdir("different");
    let a = summary(&dir, "a.json", "four-beacon-fusion", "ekf", "1");
    let b = summary(&dir, "b.json", "four-beacon-fusion-fault", "ekf", "1");
    let (code, out, err) = entrynav(&["trade", "compare", &a, &b]);
    assert_eq!(code, 0, "{out}{err}");
    assert!(
        out.contains("`four-beacon-fusion`") && out.contains("`four-beacon-fusion-fault`"),
        "both scenarios named: {out}"
    );
    // What differs, as --set paths, before the table; the headline rows lead each filter.
    let listed = out
        .split("scenario differences (A -> B):")
        .nth(1)
        .expect("no differences listed");
    assert!(
        listed.contains("name: \"four-beacon-fusion\" -> \"four-beacon-fusion-fault\""),
        "{listed}"
    );
    assert!(
        listed.contains("beacons.3."),
        "the silent orbiter: {listed}"
    );
    let v = compare_json(&a, &b, &[]);
    let diffs = v["scenario_differences"].as_array().unwrap();
    assert!(!diffs.is_empty() && diffs.len() < 20, "{diffs:?}");
    let r = rows(&v, "ekf");
    let first: Vec<&str> = r
        .iter()
        .take(5)
        .map(|r| r["state"].as_str().unwrap())
        .collect();
    assert_eq!(
        first,
        ["pos_m", "vel_mps", "downrange_m", "crossrange_m", "up_m"]
    );
    // The old flag is still accepted.
    let v2 = compare_json(&a, &b, &["--allow-different-scenarios"]);
    assert_eq!(v2["scenario_differences"], v["scenario_differences"]);
}

#[test]
fn unreadable_or_foreign_files_are_usage_errors() {
    let dir = tmpdir("bad");
    let a = summary(&dir, "a.json", "four-beacon-fusion", "ekf", "1");
    let missing = dir.join("missing.json");
    let (code, _, err) = entrynav(&["trade", "compare", &a, missing.to_str().unwrap()]);
    assert_eq!(code, 2);
    assert!(err.contains("missing.json"), "{err}");
    let foreign = dir.join("foreign.json");
    std::fs::write(&foreign, "{\"cells\": []}").unwrap();
    let (code, _, err) = entrynav(&["trade", "compare", foreign.to_str().unwrap(), &a]);
    assert_eq!(code, 2);
    assert!(err.contains("not a trade summary"), "{err}");
}

#[test]
fn paired_final_errors_reproduce_the_summary_rmse_and_narrow_the_interval() {
    let dir = tmpdir("paired");
    let run = |name: &str, sets: &[&str]| {
        let json = dir.join(format!("{name}.json"));
        let csv = dir.join(name);
        let mut args = vec![
            "trade",
            "--scenario",
            "four-beacon-fusion",
            "--filters",
            "ekf",
            "--runs",
            "20",
            "--seed",
            "4",
            "--no-pcrlb",
            "--quiet",
            "--json",
            json.to_str().unwrap(),
            "--csv-dir",
            csv.to_str().unwrap(),
        ];
        args.extend_from_slice(sets);
        let (code, _, err) = entrynav(&args);
        assert_eq!(code, 0, "{err}");
        let csv = csv.join("four-beacon-fusion_final_errors.csv");
        (
            json.to_str().unwrap().to_string(),
            csv.to_str().unwrap().to_string(),
        )
    };
    let (a, ca) = run("a", &[]);
    let (b, cb) = run("b", &["--set", "filter.update_iterations=1"]);
    let v = compare_json(
        &a,
        &b,
        &["--allow-different-scenarios", "--final-errors", &ca, &cb],
    );
    let ekf = rows(&v, "ekf");
    for state in ["pos_m", "vel_mps", "r_m"] {
        let find = |m: &str| {
            ekf.iter()
                .find(|r| r["metric"] == m && r["state"] == state)
                .unwrap_or_else(|| panic!("{m} {state} missing"))
        };
        let (summary, paired) = (find("rmse_final"), find("rmse_final_paired"));
        assert_eq!(paired["paired_runs"], 20);
        for side in ["a", "b"] {
            let (s, p) = (
                summary[side]["value"].as_f64().unwrap(),
                paired[side]["value"].as_f64().unwrap(),
            );
            assert!(
                (s - p).abs() <= 1e-9 * s,
                "{state} {side}: summary {s} vs per-run {p}"
            );
        }
        // The same seed flies the same runs: pairing removes their common spread.
        assert!(
            paired["se"].as_f64().unwrap() < summary["se"].as_f64().unwrap(),
            "{state}"
        );
    }
    let same = compare_json(&a, &a, &["--final-errors", &ca, &ca]);
    for r in rows(&same, "ekf")
        .iter()
        .filter(|r| r["metric"] == "rmse_final_paired")
    {
        assert_eq!(r["diff"], 0.0);
        assert_eq!(r["significant"], false);
    }
    let (code, _, err) = entrynav(&["trade", "compare", &a, &b, "--final-errors", &a, &cb]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("not a final-errors CSV"), "{err}");
}
