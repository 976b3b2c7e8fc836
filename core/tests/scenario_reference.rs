//! `docs/scenario-reference.md` is generated from the configuration types
//! (`entrynav::scenario::reference`): the committed file must equal the generated one, and every
//! field of every built-in scenario (resolved: defaults filled in) must have a row. Regenerate with
//! `ENTRYNAV_BLESS=1 cargo test -p entrynav --test scenario_reference`.

use entrynav::scenario::reference::{field_reference, markdown};
use entrynav::scenario::{BUILTIN_NAMES, ScenarioConfig};
use serde_json::Value;
use std::collections::BTreeSet;

fn leaves(v: &Value, path: &str, out: &mut BTreeSet<String>) {
    match v {
        Value::Object(m) => {
            for (k, x) in m {
                // A map's entries (`filter.tuned.<filter name>`) share one row.
                let k = if path == "filter.tuned" { "<name>" } else { k };
                let p = if path.is_empty() {
                    k.to_string()
                } else {
                    format!("{path}.{k}")
                };
                leaves(x, &p, out);
            }
        }
        // An array of tables: its elements' fields under `[]`; an array of numbers is a leaf.
        Value::Array(items) if items.iter().any(Value::is_object) => {
            for x in items {
                leaves(x, &format!("{path}[]"), out);
            }
        }
        _ => {
            out.insert(path.to_string());
        }
    }
}

#[test]
fn every_field_of_every_builtin_has_a_row() {
    let rows: BTreeSet<String> = field_reference().into_iter().map(|f| f.path).collect();
    let mut missing = Vec::new();
    for name in BUILTIN_NAMES {
        let cfg = ScenarioConfig::builtin(name).unwrap();
        let mut paths = BTreeSet::new();
        leaves(&serde_json::to_value(&cfg).unwrap(), "", &mut paths);
        for p in paths {
            if !rows.contains(&p) {
                missing.push(format!("{name}: {p}"));
            }
        }
    }
    assert!(missing.is_empty(), "fields without a row: {missing:?}");
    // And the rows carry what a user needs.
    let f = field_reference();
    let row = |p: &str| {
        f.iter()
            .find(|r| r.path == p)
            .unwrap_or_else(|| panic!("{p}"))
    };
    let speed = row("truth.initial.speed_mps");
    assert!(!speed.description.is_empty());
    let runs = row("monte_carlo.runs");
    assert_eq!(runs.default.as_deref(), Some("100"));
    assert!(
        runs.range.as_deref().unwrap_or("").contains("1000000"),
        "{runs:?}"
    );
    assert!(
        row("filter.tuned.<name>.q_diag")
            .description
            .contains("Process-noise")
    );
}

#[test]
fn the_committed_reference_is_the_generated_one() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../docs/scenario-reference.md");
    let generated = markdown();
    if std::env::var_os("ENTRYNAV_BLESS").is_some() {
        std::fs::write(path, &generated).unwrap();
    }
    let committed = std::fs::read_to_string(path).unwrap_or_default();
    assert!(
        committed == generated,
        "docs/scenario-reference.md is stale: regenerate it with ENTRYNAV_BLESS=1 cargo test -p entrynav --test scenario_reference"
    );
}
