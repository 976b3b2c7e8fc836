//! Outputs are whole or absent: a process killed while it writes, a disk that fills up, and two
//! studies writing one path never leave a truncated or mixed file, and never destroy the file
//! that was there before.
//!
//! The file-size limit of the process (`ulimit -f`, RLIMIT_FSIZE) makes the write fail part-way
//! through, deterministically: with SIGXFSZ at its default the kernel kills the process in the
//! middle of the write (as a SIGKILL or a power loss would); with SIGXFSZ ignored the write fails
//! with EFBIG, as on a full disk.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

fn folder(name: &str) -> PathBuf {
    let d = std::env::temp_dir().join(format!("entrynav-outputs-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&d);
    std::fs::create_dir_all(&d).unwrap();
    d
}

const PREVIOUS: &str = "{\"previous\": \"a good summary from an earlier study\"}\n";

/// A 3-run EKF trade of four-beacon-fusion writing `json` (about 7 kB), under a shell prelude.
fn trade_under(prelude: &str, json: &Path, seed: u64) -> Output {
    let script = format!("{prelude} exec \"$0\" \"$@\"");
    Command::new("sh")
        .args(["-c", &script, env!("CARGO_BIN_EXE_entrynav")])
        .args([
            "trade",
            "--scenario",
            "four-beacon-fusion",
            "--filters",
            "ekf",
        ])
        .args(["--runs", "3", "--threads", "1", "--quiet", "--no-pcrlb"])
        .args(["--seed", &seed.to_string(), "--json"])
        .arg(json)
        .output()
        .unwrap()
}

fn files_in(d: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(d)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

#[test]
fn a_process_killed_while_writing_leaves_the_previous_file_intact() {
    let d = folder("killed");
    let json = d.join("o.json");
    std::fs::write(&json, PREVIOUS).unwrap();
    // 4 blocks of 512 bytes (dash) or 1 kB (bash): less than the 7 kB summary.
    let out = trade_under("ulimit -f 4;", &json, 1);
    assert!(!out.status.success(), "the write should have been cut");
    assert_eq!(std::fs::read_to_string(&json).unwrap(), PREVIOUS);
    // What the killed process left is its temporary file, never the target's name.
    for name in files_in(&d) {
        assert!(name == "o.json" || name.ends_with(".tmp"), "{name}");
    }
}

#[test]
fn a_full_disk_is_an_error_naming_the_file_and_the_previous_file_stays() {
    let d = folder("full");
    let json = d.join("o.json");
    std::fs::write(&json, PREVIOUS).unwrap();
    let out = trade_under("trap '' XFSZ; ulimit -f 4;", &json, 1);
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    assert!(err.contains("o.json") && err.contains("too large"), "{err}");
    assert_eq!(std::fs::read_to_string(&json).unwrap(), PREVIOUS);
    assert_eq!(
        files_in(&d),
        ["o.json"],
        "the failed write removes its temporary file"
    );
}

/// The summary without what differs between two runs of the same study (timing, provenance).
fn results(text: &str) -> serde_json::Value {
    let mut v: serde_json::Value = serde_json::from_str(text)
        .unwrap_or_else(|e| panic!("not one JSON summary ({e}), {} bytes", text.len()));
    let o = v.as_object_mut().unwrap();
    o.remove("timing");
    o.remove("provenance");
    v
}

#[test]
fn two_studies_writing_one_path_leave_one_whole_summary() {
    let d = folder("race");
    // Two studies whose summaries differ (seeds 1 and 2), each alone first.
    let alone: Vec<serde_json::Value> = [1, 2]
        .iter()
        .map(|&seed| {
            let p = d.join(format!("alone{seed}.json"));
            assert!(trade_under("", &p, seed).status.success());
            results(&std::fs::read_to_string(p).unwrap())
        })
        .collect();
    assert_ne!(alone[0], alone[1]);
    let json = d.join("o.json");
    for _ in 0..12 {
        let _ = std::fs::remove_file(&json);
        std::thread::scope(|s| {
            for seed in [1, 2] {
                let json = &json;
                s.spawn(move || assert!(trade_under("", json, seed).status.success()));
            }
        });
        let written = results(&std::fs::read_to_string(&json).unwrap());
        assert!(
            alone.contains(&written),
            "a summary that is neither study's"
        );
    }
}

#[test]
fn a_failed_summary_does_not_skip_the_other_outputs_and_every_failure_is_named() {
    // Under a 2 kB limit (SIGXFSZ ignored: writes fail with EFBIG) the 7 kB summary, the
    // per-filter CSV and the report fail, the 1.2 kB final-errors CSV fits.
    let d = folder("partial");
    let script = "trap '' XFSZ; ulimit -f 4; exec \"$0\" \"$@\"";
    let out = Command::new("sh")
        .args(["-c", script, env!("CARGO_BIN_EXE_entrynav")])
        .args([
            "trade",
            "--scenario",
            "four-beacon-fusion",
            "--filters",
            "ekf",
        ])
        .args(["--runs", "3", "--threads", "1", "--quiet", "--no-pcrlb"])
        .current_dir(&d)
        .args(["--json", "o.json", "--csv-dir", "c", "--report", "r.html"])
        .output()
        .unwrap();
    let err = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(1), "{err}");
    for named in ["o.json", "four-beacon-fusion_ekf.csv", "r.html"] {
        assert!(err.contains(named), "{named} not named: {err}");
    }
    let fits = d.join("c").join("four-beacon-fusion_final_errors.csv");
    assert!(
        std::fs::read_to_string(fits)
            .unwrap()
            .starts_with("run,filter,")
    );
    assert!(!d.join("o.json").exists() && !d.join("r.html").exists());
}

#[test]
fn a_closed_standard_output_does_not_cost_a_file() {
    // `entrynav trade … --json o.json | head -0`: the tables meet a closed pipe (SIGPIPE ends
    // the process quietly), but the files are written before them.
    let d = folder("pipe");
    let mut child = Command::new(env!("CARGO_BIN_EXE_entrynav"))
        .args([
            "trade",
            "--scenario",
            "four-beacon-fusion",
            "--filters",
            "ekf",
        ])
        .args(["--runs", "3", "--threads", "1", "--quiet", "--no-pcrlb"])
        .args(["--json", "o.json", "--csv-dir", "c"])
        .current_dir(&d)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::null())
        .spawn()
        .unwrap();
    drop(child.stdout.take()); // the reader goes away before anything is printed
    let status = child.wait().unwrap();
    assert!(
        !status.success(),
        "the tables should have met the closed pipe"
    );
    let json = std::fs::read_to_string(d.join("o.json")).unwrap();
    assert!(results(&json)["filters"][0]["name"] == "ekf");
    assert!(d.join("c").join("four-beacon-fusion_ekf.csv").exists());
}
