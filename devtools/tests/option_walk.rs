//! Every option of every `entrynav-dev` subcommand, walked from clap's own command tree with
//! extreme and malformed values (issue 53), as `cli/tests/option_walk.rs` walks `entrynav`: no
//! hang, no crash, and every refusal names the option.

#[path = "../../cli/tests/option_walk/walker.rs"]
mod walker;

use entrynav_studies::fmu_pack::{PackOptions, pack_fmus};
use std::path::Path;

fn tool() -> &'static Path {
    Path::new(env!("CARGO_BIN_EXE_entrynav-dev"))
}

/// The valid, quick command line of each command, by option id.
fn base_lines(dir: &Path) -> walker::BaseLines {
    let p = |f: &str| vec![dir.join(f).display().to_string()];
    let s = |v: &str| vec![v.to_string()];
    let mut b = walker::BaseLines::new();
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
    let commands = walker::commands(&entrynav_devtools::command(), &base_lines(&dir));
    let probes = walker::checked_probes(tool(), &commands, &dir);
    assert!(probes.len() > 100, "only {} probes", probes.len());
    walker::assert_all_pass(tool(), &probes, &dir);
}
