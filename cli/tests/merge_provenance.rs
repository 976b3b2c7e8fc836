//! `trade merge` keeps what the shards' study was (issue "Nothing lost, nothing silent"): the
//! merged summary's provenance holds the shards' `--set` overrides and atmosphere source, as the
//! single-process study's does; shards of different overrides are refused; the merged files are
//! written before the tables, so a closed standard output never costs them.

mod common;

use common::{entrynav, scratch_dir};
use serde_json::Value;
use std::path::{Path, PathBuf};

const SET: &str = "filter.update_iterations=1";

fn read_json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

/// Run shard `i/2` of the study with override `set` into `dir`; returns the shard file.
fn shard(dir: &Path, i: usize, set: &str) -> PathBuf {
    let out = dir.join(format!("shard{i}-{}.json", set.len()));
    let spec = format!("{i}/2");
    let (code, _, err) = entrynav(&[
        "trade",
        "--scenario",
        "orbiters-3",
        "--filters",
        "ekf",
        "--runs",
        "300",
        "--seed",
        "4",
        "--set",
        set,
        "--shard",
        &spec,
        "--quiet",
        "--json",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    out
}

#[test]
fn merged_summary_keeps_the_overrides_and_atmosphere_of_the_study() {
    let dir = scratch_dir("merge-provenance", "keeps");
    let parts = [shard(&dir, 0, SET), shard(&dir, 1, SET)];
    let merged = dir.join("merged.json");
    let (code, _, err) = entrynav(&[
        "trade",
        "merge",
        parts[0].to_str().unwrap(),
        parts[1].to_str().unwrap(),
        "--json",
        merged.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let whole = dir.join("whole.json");
    let (code, _, err) = entrynav(&[
        "trade",
        "--scenario",
        "orbiters-3",
        "--filters",
        "ekf",
        "--runs",
        "300",
        "--seed",
        "4",
        "--set",
        SET,
        "--quiet",
        "--json",
        whole.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let (m, w) = (read_json(&merged), read_json(&whole));
    assert_eq!(
        m["provenance"]["overrides"],
        serde_json::json!([SET]),
        "{m}"
    );
    assert!(
        m["provenance"]["atmosphere"].is_object(),
        "{}",
        m["provenance"]
    );
    assert_eq!(m["provenance"]["overrides"], w["provenance"]["overrides"]);
    assert_eq!(m["provenance"]["atmosphere"], w["provenance"]["atmosphere"]);
    assert_eq!(
        m["provenance"]["scenario_fingerprint"],
        w["provenance"]["scenario_fingerprint"]
    );
    assert!(m["filters"] == w["filters"], "merged != single-process");
}

#[test]
fn shards_of_different_overrides_are_refused() {
    let dir = scratch_dir("merge-provenance", "differ");
    let a = shard(&dir, 0, SET);
    let b = shard(&dir, 1, "filter.update_iterations=2");
    let (code, _, err) = entrynav(&["trade", "merge", a.to_str().unwrap(), b.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("different studies"), "{err}");
}

#[test]
fn merge_writes_its_files_even_when_standard_output_is_closed() {
    let dir = scratch_dir("merge-provenance", "pipe");
    let parts = [shard(&dir, 0, SET), shard(&dir, 1, SET)];
    let (json, csv) = (dir.join("m.json"), dir.join("csv"));
    let cmd = format!(
        "'{}' trade merge '{}' '{}' --json '{}' --csv-dir '{}' | head -c 1 >/dev/null",
        env!("CARGO_BIN_EXE_entrynav"),
        parts[0].display(),
        parts[1].display(),
        json.display(),
        csv.display()
    );
    let status = std::process::Command::new("sh")
        .args(["-c", &cmd])
        .status()
        .unwrap();
    assert!(status.success());
    assert_eq!(read_json(&json)["complete"], true);
    assert!(
        std::fs::read_dir(&csv).unwrap().count() > 0,
        "no CSV written"
    );
}

#[test]
fn merge_reports_the_shards_summed_wall_time_and_accepts_quiet() {
    let dir = scratch_dir("merge", "wall");
    let (a, b) = (shard(&dir, 0, SET), shard(&dir, 1, SET));
    let walls: f64 = [&a, &b]
        .iter()
        .map(|p| {
            read_json(p)["wall_s"]
                .as_f64()
                .expect("shard without wall_s")
        })
        .sum();
    assert!(walls > 0.0);
    let json = dir.join("wall.json");
    let (code, out, err) = entrynav(&[
        "trade",
        "merge",
        a.to_str().unwrap(),
        b.to_str().unwrap(),
        "--quiet",
        "--json",
        json.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let first = out.lines().next().unwrap();
    assert!(
        first.ends_with("s wall summed over the 2 shards)") && !first.contains("(0.00 s"),
        "{first}"
    );
    let merged = read_json(&json)["timing"]["wall_s"].as_f64().unwrap();
    assert!((merged - walls).abs() < 1e-9, "{merged} vs {walls}");
}

#[test]
fn an_empty_shard_is_named_with_the_number_of_shards_the_study_can_use() {
    let dir = scratch_dir("merge-provenance", "empty-shard");
    let out = dir.join("s1.json");
    let (code, _, err) = entrynav(&[
        "trade",
        "--scenario",
        "orbiters-3",
        "--runs",
        "200",
        "--shard",
        "1/4",
        "--quiet",
        "--json",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains("shard 1/4 of this 200-run study holds no runs")
            && err.contains("use at most 1 shard"),
        "{err}"
    );
    // A shard that holds a block: no note.
    let (code, _, err) = entrynav(&[
        "trade",
        "--scenario",
        "orbiters-3",
        "--runs",
        "10",
        "--shard",
        "0/1",
        "--quiet",
        "--json",
        dir.join("s0.json").to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("holds no runs"), "{err}");
}

/// `trade --shard` of `msl-guided` (a scenario with `[guidance]`): shard `i` of 2 into `dir`.
fn guided_shard(dir: &Path, i: usize) -> PathBuf {
    let out = dir.join(format!("guided{i}.json"));
    let spec = format!("{i}/2");
    let (code, _, err) = entrynav(&[
        "trade",
        "--scenario",
        "msl-guided",
        "--filters",
        "ekf",
        "--runs",
        "300",
        "--seed",
        "5",
        "--shard",
        &spec,
        "--quiet",
        "--json",
        out.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    out
}

#[test]
fn merged_guided_shards_carry_the_single_process_delivery_table() {
    let dir = scratch_dir("merge-provenance", "delivery");
    let parts = [guided_shard(&dir, 0), guided_shard(&dir, 1)];
    for p in &parts {
        let runs = read_json(p)["delivery"]["runs"].as_array().unwrap().len();
        assert!(runs > 0 && runs < 300, "{}: {runs} runs", p.display());
    }
    let merged = dir.join("merged.json");
    let (code, out, err) = entrynav(&[
        "trade",
        "merge",
        parts[0].to_str().unwrap(),
        parts[1].to_str().unwrap(),
        "--json",
        merged.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    assert!(out.contains("Delivery at deployment"), "{out}");
    let whole = dir.join("whole.json");
    let (code, _, err) = entrynav(&[
        "trade",
        "--scenario",
        "msl-guided",
        "--filters",
        "ekf",
        "--runs",
        "300",
        "--seed",
        "5",
        "--quiet",
        "--json",
        whole.to_str().unwrap(),
    ]);
    assert_eq!(code, 0, "{err}");
    let (m, w) = (read_json(&merged), read_json(&whole));
    assert!(
        w["delivery"]["rows"]
            .as_array()
            .is_some_and(|r| r.len() == 3)
    );
    assert_eq!(m["delivery"], w["delivery"]);
    // A shard without deliveries (an older file) beside one with them is refused.
    let mut old = read_json(&parts[1]);
    old.as_object_mut().unwrap().remove("delivery");
    let older = dir.join("older.json");
    std::fs::write(&older, old.to_string()).unwrap();
    let (code, _, err) = entrynav(&[
        "trade",
        "merge",
        parts[0].to_str().unwrap(),
        older.to_str().unwrap(),
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("1 of 2 shards carry a delivery table"),
        "{err}"
    );
}
