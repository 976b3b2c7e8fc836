//! Checkpoints and the resume checksum of `entrynav trade` (issue "Nothing lost, nothing
//! silent"): a study killed outright (SIGKILL) keeps the work of its last checkpoint and resumes
//! from it to exactly the uninterrupted result; a killed study never leaves an older summary
//! looking current; an edited `resume` block is refused.

mod common;

use common::{entrynav, scratch_dir, spawn_with_progress};
use serde_json::Value;
use std::path::Path;

fn read_json(path: &Path) -> Value {
    serde_json::from_str(&std::fs::read_to_string(path).unwrap()).unwrap()
}

const STUDY: [&str; 7] = [
    "trade",
    "--scenario",
    "orbiters-3",
    "--filters",
    "ekf",
    "--seed",
    "7",
];

/// `STUDY` with `extra` arguments and `--json out`.
fn study<'a>(extra: &[&'a str], out: &'a Path) -> Vec<&'a str> {
    STUDY
        .iter()
        .copied()
        .chain(extra.iter().copied())
        .chain(["--json", out.to_str().unwrap()])
        .collect()
}

/// The number of runs of a `checkpoint: K runs in FILE` line.
fn checkpoint_runs(line: &str) -> Option<u64> {
    let rest = line.strip_prefix("checkpoint: ")?;
    rest.split_once(" runs")?.0.parse().ok()
}

#[test]
fn a_killed_study_resumes_from_its_last_checkpoint_to_the_uninterrupted_result() {
    let dir = scratch_dir("checkpoints", "kill-resume");
    let (killed, resumed, whole) = (
        dir.join("killed.json"),
        dir.join("resumed.json"),
        dir.join("whole.json"),
    );
    let runs = ["--runs", "3000", "--checkpoint-every", "0.1"];
    let mut child = spawn_with_progress(&study(&runs, &killed), std::process::Stdio::null());
    // Wait for a checkpoint that holds runs, then kill the study outright.
    let line = child.wait_for_line(|l| checkpoint_runs(l).is_some_and(|k| k > 0));
    let seen = checkpoint_runs(&line).unwrap();
    child.kill();
    let partial = read_json(&killed);
    assert_eq!(partial["complete"], false, "{partial}");
    let kept = partial["runs_completed"].as_u64().unwrap();
    assert!(
        kept >= seen && kept < 3000,
        "kept {kept}, checkpoint said {seen}"
    );
    assert!(
        partial["resume_checksum"]
            .as_str()
            .unwrap()
            .starts_with("fnv1a64:")
    );

    let quiet = ["--runs", "3000", "--quiet"];
    let mut resume_args = study(&quiet, &resumed);
    resume_args.extend(["--resume", killed.to_str().unwrap()]);
    let (code, _, err) = entrynav(&resume_args);
    assert_eq!(code, 0, "{err}");
    let (code, _, err) = entrynav(&study(&quiet, &whole));
    assert_eq!(code, 0, "{err}");
    let (r, w) = (read_json(&resumed), read_json(&whole));
    assert_eq!(r["complete"], true);
    assert!(r.get("resume").is_none() && r.get("resume_checksum").is_none());
    assert!(r["filters"] == w["filters"], "resumed != uninterrupted");
    assert!(r["pcrlb"] == w["pcrlb"], "resumed PCRLB != uninterrupted");
}

#[test]
fn a_study_killed_at_its_first_run_leaves_no_summary_that_looks_current() {
    // An old, complete summary of another seed sits at the path; the new study is killed as
    // soon as its first runs finish, long before the default 60 s interval.
    let dir = scratch_dir("checkpoints", "stale");
    let out = dir.join("t.json");
    let (code, _, err) = entrynav(&study(&["--runs", "5", "--quiet"], &out));
    assert_eq!(code, 0, "{err}");
    assert_eq!(read_json(&out)["complete"], true);
    let mut args = study(&["--runs", "1000000"], &out);
    args[6] = "8";
    let mut child = spawn_with_progress(&args, std::process::Stdio::null());
    child.wait_for_runs(0);
    child.kill();
    let now = read_json(&out);
    assert_eq!(
        now["complete"], false,
        "the old complete summary is still there"
    );
    assert_eq!(now["seed"], 8);
    assert_eq!(now["runs"], 1_000_000);
    assert!(now["resume"].is_object());
}

/// The first `"sum_sq"` number in `v` (depth first), for tampering.
fn first_sum_sq(v: &mut Value) -> Option<&mut Value> {
    match v {
        Value::Object(map) => {
            if map
                .get("sum_sq")
                .is_some_and(|x| x.as_f64().is_some_and(|x| x > 0.0))
            {
                return map.get_mut("sum_sq");
            }
            map.values_mut().find_map(first_sum_sq)
        }
        Value::Array(items) => items.iter_mut().find_map(first_sum_sq),
        _ => None,
    }
}

#[test]
fn an_edited_or_unchecked_resume_block_is_refused() {
    let dir = scratch_dir("checkpoints", "tamper");
    let partial = dir.join("partial.json");
    let mut child = spawn_with_progress(
        &study(&["--runs", "20000"], &partial),
        std::process::Stdio::null(),
    );
    child.wait_for_runs(0);
    child.interrupt();
    let end = child.finish(60);
    assert_eq!(end.status.code(), Some(130), "{}", end.err);
    let good = read_json(&partial);
    let resume_from = |v: &Value, name: &str| {
        let file = dir.join(name);
        std::fs::write(&file, serde_json::to_string_pretty(v).unwrap()).unwrap();
        let out = dir.join(format!("out-{name}"));
        let mut args = study(&["--runs", "1000000", "--quiet"], &out);
        args.extend([
            "--resume",
            file.to_str().unwrap(),
            "--checkpoint-every",
            "0",
        ]);
        // A resume that is accepted runs a million runs: it must be refused at once.
        let (code, _, err) = entrynav(&args);
        (code, err)
    };
    // One sum of squares multiplied by 10 (it moved a final RMSE 0.587 -> 0.939 m silently).
    let mut tampered = good.clone();
    let x = first_sum_sq(&mut tampered["resume"]).expect("a sum_sq in the resume block");
    *x = Value::from(x.as_f64().unwrap() * 10.0);
    let (code, err) = resume_from(&tampered, "tampered.json");
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("does not match its checksum"), "{err}");
    // A block without its checksum.
    let mut unchecked = good.clone();
    unchecked.as_object_mut().unwrap().remove("resume_checksum");
    let (code, err) = resume_from(&unchecked, "unchecked.json");
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("no `resume_checksum`"), "{err}");
}

#[test]
fn checkpoint_interval_is_bounded_and_needs_a_json_file() {
    let dir = scratch_dir("checkpoints", "flags");
    let out = dir.join("t.json");
    for bad in ["-1", "0.01", "1e9", "NaN"] {
        let (code, _, err) = entrynav(&study(&["--runs", "5", "--checkpoint-every", bad], &out));
        assert_eq!(code, 2, "{bad}: {err}");
        assert!(
            err.contains("--checkpoint-every") && err.contains("86400"),
            "{err}"
        );
    }
    let (code, _, err) = entrynav(&[
        "trade",
        "--scenario",
        "orbiters-3",
        "--runs",
        "5",
        "--checkpoint-every",
        "5",
    ]);
    assert_eq!(code, 2, "{err}");
    assert!(err.contains("needs --json FILE"), "{err}");
    assert!(!out.exists(), "a refused study wrote {}", out.display());
}
