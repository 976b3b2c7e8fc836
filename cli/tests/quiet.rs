//! `--quiet` means the same in every command: no progress on standard error, the same results on
//! standard output.

mod common;
use common::entrynav;

/// Standard output without the lines that carry wall-clock times.
fn reproducible(out: &str) -> Vec<&str> {
    out.lines()
        .filter(|l| !l.contains(" s wall") && !l.contains("µs per filter step"))
        .collect()
}

#[test]
fn trade_quiet_prints_the_same_tables_and_nothing_on_stderr() {
    let args = [
        "trade",
        "--scenario",
        "four-beacon-fusion",
        "--filters",
        "ekf",
        "--runs",
        "5",
        "--no-pcrlb",
    ];
    let (code, loud, _) = entrynav(&args);
    assert_eq!(code, 0);
    let quiet_args: Vec<&str> = args.iter().copied().chain(["--quiet"]).collect();
    let (code, out, err) = entrynav(&quiet_args);
    assert_eq!(code, 0, "{err}");
    assert!(err.is_empty(), "--quiet left this on stderr: {err}");
    assert!(out.contains("filter ekf") && out.contains("ANEES"), "{out}");
    assert_eq!(reproducible(&out), reproducible(&loud));
}

#[test]
fn train_density_quiet_drops_the_epoch_and_run_logs_but_not_the_results() {
    let dir = std::env::temp_dir().join(format!("entrynav-quiet-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let net = dir.join("net.toml");
    let args = [
        "train-density",
        "--scenario",
        "msl-airdata",
        "--trajectories",
        "4",
        "--epochs",
        "20",
        "--evaluate",
        "4",
        "--filters",
        "uskf-nn",
        "--out",
        net.to_str().unwrap(),
    ];
    let (code, loud, loud_err) = entrynav(&args);
    assert_eq!(code, 0, "{loud_err}");
    // Progress goes to stderr, never into the results on stdout.
    assert!(
        loud_err.contains("epoch") && loud_err.contains("4/4 runs"),
        "{loud_err}"
    );
    assert!(!loud.contains("train MSE"), "progress on stdout:\n{loud}");
    let quiet_args: Vec<&str> = args.iter().copied().chain(["--quiet"]).collect();
    let (code, out, err) = entrynav(&quiet_args);
    assert_eq!(code, 0, "{err}");
    assert!(err.is_empty(), "--quiet left this on stderr: {err}");
    assert!(
        out.contains("wrote") && out.contains("density RMSPE"),
        "{out}"
    );
    assert!(
        out.contains("uskf-nn"),
        "the evaluation table is missing:\n{out}"
    );
    assert_eq!(
        out.lines().count(),
        loud.lines().count(),
        "{out}\n---\n{loud}"
    );
}

#[test]
fn progress_reaches_a_log_file_as_timed_lines_when_stderr_is_not_a_terminal() {
    // The bar would be invisible in a log: a line every ENTRYNAV_PROGRESS_INTERVAL_S instead.
    let out = std::process::Command::new(env!("CARGO_BIN_EXE_entrynav"))
        .args([
            "trade",
            "--scenario",
            "four-beacon-fusion",
            "--filters",
            "ekf,dcifaif",
        ])
        .args(["--runs", "400", "--threads", "1", "--no-pcrlb"])
        .env("ENTRYNAV_PROGRESS_INTERVAL_S", "0.05")
        .env_remove("ENTRYNAV_PROGRESS")
        .output()
        .unwrap();
    assert!(out.status.success());
    let err = String::from_utf8_lossy(&out.stderr);
    let lines: Vec<&str> = err
        .lines()
        .filter(|l| l.starts_with("progress: "))
        .collect();
    assert!(lines.len() >= 2, "{err}");
    assert!(
        lines
            .iter()
            .all(|l| l.contains("/400 runs (") && l.contains(" s, eta ")),
        "{err}"
    );
    // --quiet still means nothing.
    let quiet = std::process::Command::new(env!("CARGO_BIN_EXE_entrynav"))
        .args([
            "trade",
            "--scenario",
            "four-beacon-fusion",
            "--filters",
            "ekf",
        ])
        .args(["--runs", "100", "--quiet", "--no-pcrlb"])
        .env("ENTRYNAV_PROGRESS_INTERVAL_S", "0.01")
        .output()
        .unwrap();
    assert!(quiet.stderr.is_empty());
}
