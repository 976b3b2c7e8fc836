//! Tests of the loader: built-ins, files, overrides and the files a scenario refers to.

use crate::{Base, Origin, apply_overrides, load, resolve, suggestion};
use entrynav::scenario::ScenarioConfig;

#[test]
fn builtins_files_and_overrides() {
    let s = load("four-beacon-fusion", &[], Base::Nowhere).unwrap();
    assert_eq!(s.config.name, "four-beacon-fusion");
    let dir = std::env::temp_dir().join(format!("entrynav-loader-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let text = entrynav::scenario::builtin_toml("msl-pressure").unwrap();
    std::fs::write(dir.join("mine.toml"), text).unwrap();
    let src = resolve("mine.toml", Base::Folder(&dir)).unwrap();
    assert_eq!(src.origin, Origin::File(dir.join("mine.toml")));
    assert_eq!(src.dir, dir);
    let cfg = apply_overrides(src.config, &["truth.density_bias=0.05".into()]).unwrap();
    assert_eq!(cfg.truth.density_bias, 0.05);
    // Errors name what was asked for and why.
    let e = resolve("nope.toml", Base::Folder(&dir))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("nope.toml") && e.contains("four-beacon-fusion"),
        "{e}"
    );
    let e = resolve("nope.toml", Base::Nowhere).unwrap_err().to_string();
    assert!(e.contains("no folder"), "{e}");
    let e = apply_overrides(cfg.clone(), &["truth.density_bias".into()])
        .unwrap_err()
        .to_string();
    assert!(e.contains("PATH=VALUE"), "{e}");
    let e = apply_overrides(cfg, &["truth.density_bias=11".into()])
        .unwrap_err()
        .to_string();
    assert!(e.contains("truth.density_bias"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn an_unreadable_file_keeps_the_operating_systems_error_as_its_source() {
    let dir = std::env::temp_dir().join(format!("entrynav-loader-src-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let e = resolve("missing.toml", Base::Folder(&dir)).unwrap_err();
    let io = std::error::Error::source(&e)
        .and_then(|s| s.downcast_ref::<std::io::Error>())
        .expect("the io::Error is the source");
    assert_eq!(io.kind(), std::io::ErrorKind::NotFound);
    // The message names the path; the reason is the source's, not repeated in the message.
    let text = e.to_string();
    assert!(
        text.contains(&dir.join("missing.toml").display().to_string()),
        "{text}"
    );
    assert!(!text.contains(&io.to_string()), "{text}");
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn numeric_keys_index_arrays() {
    let cfg = ScenarioConfig::builtin("ground-beacons-3").unwrap();
    let sets = [
        "beacons.1.lat_deg=-28.0".to_string(),
        "filter.q_diag.3=2e-7".to_string(),
    ];
    let out = apply_overrides(cfg, &sets).unwrap();
    assert_eq!(out.filter.q_diag[3], 2e-7);
    let text = out.to_toml_string();
    assert!(text.contains("lat_deg = -28.0"), "{text}");
    let cfg = ScenarioConfig::builtin("ground-beacons-3").unwrap();
    let err = apply_overrides(cfg, &["beacons.3.lat_deg=1".to_string()])
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("index 3 is past the array's 3 entries"),
        "{err}"
    );
}

#[test]
fn a_near_miss_of_a_builtin_name_gets_did_you_mean() {
    let err = resolve("msl-airdta", Base::CurrentDir)
        .err()
        .unwrap()
        .to_string();
    assert!(err.ends_with("; did you mean 'msl-airdata'?"), "{err}");
    let err = resolve("Ground-Beacon-3", Base::Nowhere)
        .err()
        .unwrap()
        .to_string();
    assert!(err.ends_with("; did you mean 'ground-beacons-3'?"), "{err}");
    // Far from every name: no guess.
    let err = resolve("my-entry.toml", Base::CurrentDir)
        .err()
        .unwrap()
        .to_string();
    assert!(!err.contains("did you mean"), "{err}");
    assert_eq!(suggestion("orbiters-3"), "");
}
