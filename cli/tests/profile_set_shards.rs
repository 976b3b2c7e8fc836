//! A Mars-GRAM Monte Carlo profile set (run k flies profile k mod n) gives the same study sharded
//! and merged as in one process: the profile is chosen from the run index alone.

mod common;
use common::entrynav;
use std::path::Path;

/// The summary without what may differ between processes (timing, command line).
fn stable(path: &Path) -> serde_json::Value {
    let mut v: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap();
    let o = v.as_object_mut().unwrap();
    o.remove("timing");
    o.remove("provenance");
    v
}

#[test]
fn sharded_profile_set_study_equals_the_single_process_one() {
    let set = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../core/tests/data/gram/montecarlo-3.txt"
    );
    let dir = std::env::temp_dir().join(format!("entrynav-set-shards-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let common = [
        "trade",
        "--scenario",
        "msl-airdata",
        "--filters",
        "ukf-ac",
        "--runs",
        "7",
        "--seed",
        "4",
        "--quiet",
        "--atmosphere-file",
        set,
    ];
    let whole = dir.join("whole.json");
    let (code, out, err) = entrynav(&[&common[..], &["--json", whole.to_str().unwrap()]].concat());
    assert_eq!(code, 0, "{err}");
    assert!(
        format!("{out}{err}").contains("profile"),
        "the profile-set note is shown: {out}{err}"
    );
    let mut shards = Vec::new();
    for i in 0..3 {
        let p = dir.join(format!("shard{i}.json"));
        let spec = format!("{i}/3");
        let (code, _, err) = entrynav(
            &[
                &common[..],
                &["--shard", &spec, "--json", p.to_str().unwrap()],
            ]
            .concat(),
        );
        assert_eq!(code, 0, "shard {spec}: {err}");
        shards.push(p);
    }
    let merged = dir.join("merged.json");
    let mut args = vec!["trade", "merge", "--json", merged.to_str().unwrap()];
    args.extend(shards.iter().map(|p| p.to_str().unwrap()));
    let (code, _, err) = entrynav(&args);
    assert_eq!(code, 0, "{err}");
    let (a, b) = (stable(&whole), stable(&merged));
    assert_eq!(a["filters"], b["filters"], "per-filter statistics differ");
    assert_eq!(
        a["atmosphere"], b["atmosphere"],
        "atmosphere provenance differs"
    );
    assert_eq!(a, b);
    // A different profile assignment would change the result: one profile only differs.
    let one = dir.join("one.json");
    let (code, _, err) = entrynav(
        &[
            &common[..],
            &["--atmosphere-profile", "1", "--json", one.to_str().unwrap()],
        ]
        .concat(),
    );
    assert_eq!(code, 0, "{err}");
    assert_ne!(stable(&one)["filters"], a["filters"]);
    std::fs::remove_dir_all(&dir).ok();
}
