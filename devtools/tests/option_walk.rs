//! Every option of every `entrynav-dev` subcommand, walked from clap's own command tree with
//! extreme and malformed values (issue 53), as `cli/tests/option_walk.rs` walks `entrynav`: no
//! hang, no crash, and every refusal names the option.

#[path = "../../cli/tests/option_walk/walker.rs"]
mod walker;

use entrynav_studies::fmu_pack::{PackOptions, pack_fmus};
use std::collections::BTreeMap;
use std::path::Path;

fn tool() -> &'static Path {
    Path::new(env!("CARGO_BIN_EXE_entrynav-dev"))
}

/// The valid, quick command line of each command, by option id.
fn base_lines(dir: &Path) -> BTreeMap<String, Vec<(&'static str, Vec<String>)>> {
    let p = |f: &str| vec![dir.join(f).display().to_string()];
    let s = |v: &str| vec![v.to_string()];
    let mut b = BTreeMap::new();
    b.insert(
        "fmu check".to_string(),
        vec![("file", p("fmus/MarsEntryTruth.fmu")), ("step", s("1"))],
    );
    b.insert(
        "fmu run".to_string(),
        vec![("stop", s("20")), ("step", s("1")), ("out", p("run.csv"))],
    );
    b.insert(
        "fmu fuzz".to_string(),
        vec![("file", p("fmus/MarsEntryTruth.fmu")), ("calls", s("200"))],
    );
    b.insert(
        "fmu cross-check".to_string(),
        vec![
            ("fmus", p("fmus/MarsEntryTruth.fmu")),
            ("out", p("cross-check")),
        ],
    );
    b
}

#[test]
fn every_option_of_every_developer_tool_refuses_extreme_values_by_name_and_in_time() {
    let dir = walker::scratch("dev");
    // The FMUs the tools read, packed with the library built beside this binary.
    let lib = tool().parent().unwrap().join("libentrynav_fmu.so");
    assert!(
        lib.is_file(),
        "{} missing: build the workspace first (cargo build --release --workspace, as \
         scripts/test.sh does)",
        lib.display()
    );
    let options = PackOptions {
        keep_symbols: true,
        ..PackOptions::default()
    };
    pack_fmus(&lib, &dir.join("fmus"), None, &options).expect("pack the FMUs");
    let bases = base_lines(&dir);
    let values = walker::extreme_values(&dir);
    let mut probes = Vec::new();
    for (i, leaf) in walker::leaves(&entrynav_devtools::command())
        .into_iter()
        .enumerate()
    {
        let key = leaf.path.join(" ");
        let base: BTreeMap<String, Vec<String>> = bases
            .get(&key)
            .unwrap_or_else(|| panic!("no base line for `entrynav-dev {key}`"))
            .iter()
            .map(|(id, v)| (id.to_string(), v.clone()))
            .collect();
        for id in base.keys() {
            assert!(
                leaf.options.iter().any(|o| o.id == *id),
                "`entrynav-dev {key}` has no option `{id}`"
            );
        }
        let args = walker::line(&leaf, &base, None);
        let out = walker::run(tool(), &args, &dir, 100_000 + i);
        assert_eq!(
            out.code,
            Some(0),
            "the base line `entrynav-dev {}` does not run cleanly ({:.1} s): {}",
            args.join(" "),
            out.seconds,
            out.stderr
        );
        probes.extend(walker::probes(&leaf, &base, &values));
    }
    assert!(probes.len() > 100, "only {} probes", probes.len());
    let threads = std::thread::available_parallelism().map_or(2, |n| n.get());
    let failures = walker::run_all(tool(), &probes, &dir, threads);
    assert!(
        failures.is_empty(),
        "{} of {} probes failed:\n{}",
        failures.len(),
        probes.len(),
        failures.join("\n")
    );
}
