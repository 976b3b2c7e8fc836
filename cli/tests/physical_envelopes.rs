//! No absurd input accepted in silence (issue "Nothing lost, nothing silent"): measurement noise
//! and table densities outside their physical envelopes are refused at load, naming the field,
//! or the file, line and column; a table that would have made the truth non-finite (truncated
//! mid-number, subnormal densities, a radius column read as density) is refused the same way.

mod common;

use common::{entrynav, scratch_dir};
use std::path::Path;

/// The averaged Mars-GRAM table of the core's tests (read at run time: a crate embeds only its
/// own files).
fn averaged() -> String {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../core/tests/data/gram/averaged.txt"
    );
    std::fs::read_to_string(path).expect("core/tests/data/gram/averaged.txt")
}

/// `atmosphere inspect` of `text` written to `dir/name`, with extra arguments.
fn inspect(dir: &Path, name: &str, text: &str, extra: &[&str]) -> (i32, String) {
    let f = dir.join(name);
    std::fs::write(&f, text).unwrap();
    let mut args = vec!["atmosphere", "inspect", f.to_str().unwrap()];
    args.extend_from_slice(extra);
    let (code, _, err) = entrynav(&args);
    (code, err)
}

/// The averaged Mars-GRAM table with data line `line` (1-based) edited by `edit`.
fn edited(line: usize, edit: impl Fn(&str) -> String) -> String {
    averaged()
        .lines()
        .enumerate()
        .map(|(i, l)| {
            if i + 1 == line {
                edit(l)
            } else {
                l.to_string()
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
}

#[test]
fn table_densities_outside_the_physical_envelope_are_refused_with_file_and_line() {
    let d = scratch_dir("envelopes", "tables");
    let table = averaged();
    let (code, err) = inspect(&d, "ok.txt", &table, &[]);
    assert_eq!(code, 0, "{err}");
    // 1.0E+03 kg/m3 on one row (528 g at 50 km) and 1e300.
    for (name, value) in [("big.txt", "1.000E+03"), ("huge.txt", "1.000E+300")] {
        let text = edited(4, |l| l.replacen("6.689E-03", value, 2));
        let (code, err) = inspect(&d, name, &text, &[]);
        assert_eq!(code, 2, "{name}: {err}");
        assert!(
            err.contains(name) && err.contains("line 4") && err.contains("DENSTOT"),
            "{err}"
        );
        assert!(err.contains("physical envelope"), "{err}");
    }
    // A subnormal density.
    let text = edited(4, |l| l.replacen("6.689E-03", "1.0E-310", 2));
    let (code, err) = inspect(&d, "subnormal.txt", &text, &[]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("line 4") && err.contains("physical envelope"),
        "{err}"
    );
    // The radius column read as density.
    let (code, err) = inspect(
        &d,
        "radius.txt",
        &table,
        &["--atmosphere-density-column", "Radius"],
    );
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("radius.txt") && err.contains("Radius") && err.contains("line 2"),
        "{err}"
    );
    // Truncated in the middle of a number: the cut number is malformed or out of the envelope.
    let cut = table.find("1.166E-02").unwrap() + 3;
    let (code, err) = inspect(&d, "cut.txt", &table[..cut], &[]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("cut.txt") && err.contains("line 3"), "{err}");
}

#[test]
fn beacon_noise_outside_its_envelope_is_refused_naming_the_field() {
    let d = scratch_dir("envelopes", "noise");
    let text = entrynav::scenario::builtin_toml("ground-beacons-3").unwrap();
    assert!(text.contains("range_sigma_m = 100.0"));
    let text = text.replacen("range_sigma_m = 100.0", "range_sigma_m = 1e308", 1);
    let f = d.join("s.toml");
    std::fs::write(&f, text).unwrap();
    let (code, _, err) = entrynav(&["simulate", "--scenario", f.to_str().unwrap()]);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("beacons[0].range_sigma_m") && err.contains("<= 100000 m"),
        "{err}"
    );
}

#[test]
fn implausible_entry_values_are_refused_with_the_likely_slip_unless_allowed() {
    let base = [
        "simulate",
        "--scenario",
        "four-beacon-fusion",
        "--out",
        "/dev/null",
    ];
    // A built-in: no warning.
    let (code, _, err) = entrynav(&base);
    assert_eq!(code, 0, "{err}");
    assert!(!err.contains("warning:"), "{err}");
    // A speed in km/s: refused (exit 2) with its plausible range, the likely unit and the way to
    // insist.
    let mut args = base.to_vec();
    args.extend(["--set", "truth.initial.speed_mps=5.515"]);
    let (code, _, err) = entrynav(&args);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("truth.initial.speed_mps = 5.515 is outside what a Mars entry plausibly has")
            && err.contains("km/s? 5.515 km/s = 5515 m/s")
            && err.contains("--set allow_implausible=true"),
        "{err}"
    );
    // A flight-path angle in radians, likewise.
    let mut args = base.to_vec();
    args.extend(["--set", "filter.initial.fpa_deg=-0.21"]);
    let (code, _, err) = entrynav(&args);
    assert_eq!(code, 2, "{err}");
    assert!(
        err.contains("filter.initial.fpa_deg = -0.21")
            && err.contains("radians? -0.21 rad = -12.0°"),
        "{err}"
    );
    // Insisted on: the study runs, and says on standard error what it runs with.
    args.extend([
        "--set",
        "truth.initial.speed_mps=5.6",
        "--set",
        "allow_implausible=true",
    ]);
    let (code, _, err) = entrynav(&args);
    assert_eq!(code, 0, "{err}");
    assert!(
        err.contains(
            "warning: truth.initial.speed_mps = 5.6 is outside what a Mars entry plausibly has"
        ) && err.contains("km/s? 5.6 km/s = 5600 m/s")
            && err.contains("warning: filter.initial.fpa_deg = -0.21"),
        "{err}"
    );
}
