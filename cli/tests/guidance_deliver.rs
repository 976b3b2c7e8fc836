//! `entrynav guidance deliver`: the delivery Monte Carlo with a filter in the guidance loop, its
//! JSON, its reproducibility across thread counts, and its refusals.

mod common;

use common::{entrynav, scratch_dir};
use serde_json::Value;

const GUIDANCE: &str =
    "guidance={algorithm=\"apollo\",reference_bank_deg=60.0,trigger={speed_mps=450.0}}";

fn deliver(threads: &str, json: &str) -> (i32, String, String) {
    entrynav(&[
        "guidance",
        "deliver",
        "--scenario",
        "msl-airdata",
        "--set",
        GUIDANCE,
        "--filters",
        "ekf",
        "--runs",
        "6",
        "--seed",
        "28",
        "--threads",
        threads,
        "--json",
        json,
    ])
}

#[test]
fn deliver_writes_rows_for_perfect_navigation_unguided_and_each_filter() {
    let (code, out, err) = deliver("2", "-");
    assert_eq!(code, 0, "{err}");
    let v: Value = serde_json::from_str(&out).unwrap();
    let rows = v["delivery"]["rows"].as_array().unwrap();
    let names: Vec<&str> = rows.iter().map(|r| r["name"].as_str().unwrap()).collect();
    assert_eq!(names, ["perfect-nav", "unguided", "ekf"]);
    for r in rows {
        assert_eq!(
            r["deployed"].as_u64().unwrap() + r["failures"].as_u64().unwrap(),
            6
        );
        assert_eq!(r["rate_limit_held"], true);
    }
    // Every run has one entry per row: a delivery or a failure.
    let runs = v["runs"].as_array().unwrap();
    assert_eq!(runs.len(), 18);
    for r in runs {
        assert!(r["delivery"].is_object() != r["failure"].is_string(), "{r}");
    }
    // Same answer on one thread.
    let (code, one, err) = deliver("1", "-");
    assert_eq!(code, 0, "{err}");
    assert_eq!(out, one);
}

#[test]
fn deliver_writes_its_json_file_and_prints_the_table() {
    let dir = scratch_dir("guidance", "file");
    let path = dir.join("delivery.json");
    let (code, out, err) = deliver("2", path.to_str().unwrap());
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("Delivery at deployment"), "{out}");
    assert!(out.contains("99% ellipse"), "{out}");
    let v: Value = serde_json::from_str(&std::fs::read_to_string(&path).unwrap()).unwrap();
    assert_eq!(v["delivery"]["runs"], 6);
}

#[test]
fn deliver_refuses_a_scenario_without_guidance_and_a_bad_run_count() {
    let (code, _, err) = entrynav(&["guidance", "deliver", "--scenario", "msl-airdata"]);
    assert_ne!(code, 0);
    assert!(err.contains("no [guidance] section"), "{err}");
    let (code, _, err) = entrynav(&[
        "guidance",
        "deliver",
        "--scenario",
        "msl-airdata",
        "--runs",
        "0",
    ]);
    assert_eq!(code, 2);
    assert!(
        err.contains("--runs") && err.contains("0 is not a run count: give 1 to"),
        "{err}"
    );
}
