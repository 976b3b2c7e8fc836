//! `trade --grid` with a guided cell (issue 28): a cell whose scenario has `[guidance]` carries
//! each filter's delivery at deployment, equal to `entrynav guidance deliver` on the same
//! scenario, runs and seed; a cell without `[guidance]` carries none; `GRID.md` gets the
//! delivery table and `GRID.csv` its columns.

mod common;

use common::{entrynav, scratch_dir};
use serde_json::Value;

#[test]
fn a_guided_grid_cell_carries_the_delivery_of_guidance_deliver() {
    let dir = scratch_dir("grid-delivery", "cells");
    let grid = dir.join("g.toml");
    std::fs::write(
        &grid,
        "name = \"g\"\nruns = 30\nseed = 2\nfilters = [\"ekf\"]\nscenarios = [\"msl-guided\", \"msl-airdata\"]\n",
    )
    .unwrap();
    let out_dir = dir.join("out");
    let (code, _, err) = entrynav(&[
        "trade",
        "--grid",
        grid.to_str().unwrap(),
        "--out-dir",
        out_dir.to_str().unwrap(),
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
    let doc: Value =
        serde_json::from_str(&std::fs::read_to_string(out_dir.join("g.json")).unwrap()).unwrap();
    let cells = doc["cells"].as_array().unwrap();
    assert_eq!(cells.len(), 2);
    assert!(cells[1].get("delivery").is_none(), "{}", cells[1]);
    let cell = &cells[0]["delivery"];
    let (code, out, err) = entrynav(&[
        "guidance",
        "deliver",
        "--scenario",
        "msl-guided",
        "--filters",
        "ekf",
        "--runs",
        "30",
        "--seed",
        "2",
        "--json",
        "-",
    ]);
    assert_eq!(code, 0, "{err}");
    let deliver: Value = serde_json::from_str(&out).unwrap();
    let rows = deliver["delivery"]["rows"].as_array().unwrap();
    let row = |name: &str| rows.iter().find(|r| r["name"] == name).unwrap();
    let (ekf, perfect) = (row("ekf"), row("perfect-nav"));
    assert_eq!(cell["rms_miss_m"], ekf["rms_miss_m"]);
    assert_eq!(cell["failures"], ekf["failures"]);
    assert_eq!(
        cell["ellipse_99_semi_major_m"],
        ekf["ellipse_99"]["semi_major_m"]
    );
    assert_eq!(cell["perfect_nav_rms_miss_m"], perfect["rms_miss_m"]);
    assert!(cell["rms_miss_m"].as_f64().unwrap() > 0.0);
    let md = std::fs::read_to_string(out_dir.join("g.md")).unwrap();
    assert!(md.contains("## Delivery at deployment"), "{md}");
    let csv = std::fs::read_to_string(out_dir.join("g.csv")).unwrap();
    assert!(csv.lines().next().unwrap().contains("delivery_rms_miss_m"));
}
