//! `entrynav fmu fuzz` on the FMI 3.0 FMUs: `fmu pack --fmi 3` writes the three models, and the
//! fuzzer (chosen by the description's `fmiVersion`) drives random fmi3 call sequences through
//! our host on each. Acceptance (issue "FMI 3.0", fuzzing): no crash and no failed check; the
//! statistics it prints show every kind of call was made (illegal and refused calls, huge and
//! tiny steps, counts over their bounds, `nValues` mismatches, unknown references, null arrays,
//! unsupported functions, refused instantiations, FMU-state round trips, array checks).
//!
//! The library packed is the one `fmu pack` finds (`ENTRYNAV_FMU_LIB`, else the one built next to
//! `entrynav`: run `cargo test --workspace` or build `-p entrynav-fmu` so that it is current).
//! CI (`cargo test --workspace --release`) runs [`RELEASE_CALLS`] calls per FMU; an unoptimised
//! build far fewer (a step of the combined model is ~50 times slower there);
//! `ENTRYNAV_FUZZ3_CALLS=1000000` is the long mode.

mod common;

use common::entrynav;
use std::path::Path;

/// Calls per FMU in an optimised build.
const RELEASE_CALLS: usize = 100_000;
/// The models and the calls per FMU in an unoptimised build.
const MODELS: [(&str, usize); 3] = [
    ("MarsEntryNav", 2_000),
    ("MarsEntryNavFilter", 20_000),
    ("MarsEntryTruth", 20_000),
];

/// The number just before `phrase` in `line` (`"12 calls"` → 12 for `" calls"`).
fn count_before(line: &str, phrase: &str) -> usize {
    let end = line
        .find(phrase)
        .unwrap_or_else(|| panic!("no '{phrase}' in: {line}"));
    let digits: String = line[..end]
        .chars()
        .rev()
        .take_while(char::is_ascii_digit)
        .collect::<Vec<_>>()
        .into_iter()
        .rev()
        .collect();
    digits
        .parse()
        .unwrap_or_else(|_| panic!("no number before '{phrase}' in: {line}"))
}

fn pack(fmi: &str, out: &Path) {
    let (code, stdout, err) =
        entrynav(&["fmu", "pack", "--fmi", fmi, "--out", out.to_str().unwrap()]);
    assert_eq!(code, 0, "fmu pack --fmi {fmi} failed:\n{stdout}\n{err}");
}

#[test]
fn the_fuzzer_drives_every_fmi3_fmu_without_a_failure() {
    let dir = common::scratch_dir("fuzz3", "fmus");
    pack("3", &dir);
    let long: Option<usize> = std::env::var("ENTRYNAV_FUZZ3_CALLS")
        .ok()
        .map(|v| v.parse().expect("ENTRYNAV_FUZZ3_CALLS is a number"));
    for (model, debug_calls) in MODELS {
        let calls = long.unwrap_or(if cfg!(debug_assertions) {
            debug_calls
        } else {
            RELEASE_CALLS
        });
        let fmu = dir.join(format!("{model}-fmi3.fmu"));
        let calls_arg = calls.to_string();
        let args = [
            "fmu",
            "fuzz",
            fmu.to_str().unwrap(),
            "--calls",
            &calls_arg,
            "--seed",
            "7",
        ];
        let (code, out, err) = entrynav(&args);
        assert_eq!(code, 0, "{model}: the fuzzer failed:\n{out}\n{err}");
        assert!(
            err.is_empty(),
            "{model}: standard error is not empty:\n{err}"
        );
        let line = out
            .lines()
            .find(|l| l.starts_with(&format!("fuzz {model} (FMI 3.0): ")))
            .unwrap_or_else(|| panic!("{model}: no statistics line in:\n{out}"));
        println!("{line}");
        assert!(
            line.contains("no crash") && line.contains("Fatal 0"),
            "{line}"
        );
        let n = |phrase: &str| count_before(line, phrase);
        assert!(n(" calls in ") >= calls, "{line}");
        assert!(
            n(" illegal or refused calls answered fmi3Error") > calls / 100,
            "{line}"
        );
        assert!(n(" steps done") > calls / 100, "{line}");
        assert!(n(" huge and ") > calls / 1000, "{line}");
        assert!(n(" tiny steps") > calls / 1000, "{line}");
        assert!(n(" arguments over a bound") > calls / 1000, "{line}");
        for phrase in [
            " nValues mismatches",
            " unknown or mistyped references",
            " null arrays",
            " calls of unsupported functions",
            " instantiations refused",
            " calls on freed or null instances",
            " FMU states serialised, deserialised and serialised again identically",
            " log messages",
        ] {
            assert!(n(phrase) > 0, "{model}: no{phrase}: {line}");
        }
        // The arrays exist in the models with a filter only.
        let arrays = n(" array reads checked against the scalars");
        assert_eq!(arrays > 0, model != "MarsEntryTruth", "{line}");
        if model == "MarsEntryNavFilter" && calls >= RELEASE_CALLS {
            assert!(
                n(" refused for their work") > 0,
                "no step was refused for its work: {line}"
            );
        }
    }
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn an_fmi2_fmu_is_still_fuzzed_through_fmi2() {
    let dir = common::scratch_dir("fuzz3", "fmi2");
    pack("2", &dir);
    let fmu = dir.join("MarsEntryNavFilter.fmu");
    let (code, out, err) = entrynav(&["fmu", "fuzz", fmu.to_str().unwrap(), "--calls", "2000"]);
    assert_eq!(code, 0, "{out}\n{err}");
    assert!(
        out.contains("fuzz MarsEntryNavFilter: ") && out.contains("answered fmi2Error"),
        "{out}"
    );
    assert!(!out.contains("FMI 3.0"), "{out}");
    let _ = std::fs::remove_dir_all(&dir);
}
