//! `entrynav tune` checks its own answer (issue "Beacon designs that navigate better, and say
//! so"): a tuning that makes a filter worse on the fresh validation runs is refused unless
//! `--force`, naming the filter and the figure, and the written numbers have at most six
//! significant digits.

mod common;

use common::{entrynav, scratch_dir};

/// msl-airdata, EKF and UKF tuned on innovations alone with a small budget: the UKF's final
/// position RMSE on the fresh runs grows by more than 10 %.
const WORSE: [&str; 15] = [
    "tune",
    "--scenario",
    "msl-airdata",
    "--filter",
    "ekf,ukf",
    "--nis-only",
    "--runs",
    "12",
    "--validation-runs",
    "50",
    "--max-evaluations",
    "60",
    "--quiet",
    "--threads",
    "2",
];

#[test]
fn a_tuning_worse_than_the_input_is_refused_unless_forced() {
    let dir = scratch_dir("tune", "verdict");
    let out = dir.join("t.toml");
    let mut args = WORSE.to_vec();
    args.extend(["--out", out.to_str().unwrap()]);
    let (code, _, err) = entrynav(&args);
    assert_eq!(code, 1, "{err}");
    assert!(err.contains("not written") && err.contains("ukf:"), "{err}");
    assert!(err.contains("final position RMSE"), "{err}");
    assert!(!out.exists(), "a refused tuning wrote {}", out.display());

    args.push("--force");
    let (code, _, err) = entrynav(&args);
    assert_eq!(code, 0, "{err}");
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(
        text.contains("written with --force although worse"),
        "{text}"
    );
    // Numbers in value positions have at most six significant digits (no 0.0000000000000205...).
    let q = text
        .split("q_diag = [")
        .nth(1)
        .unwrap()
        .split(']')
        .next()
        .unwrap();
    for v in q.split(',').map(str::trim).filter(|v| !v.is_empty()) {
        let mantissa = v.split(['e', 'E']).next().unwrap();
        let digits = mantissa
            .chars()
            .filter(char::is_ascii_digit)
            .collect::<String>();
        let significant = digits.trim_start_matches('0').len();
        assert!(
            significant <= 6,
            "q_diag entry {v} has {significant} significant digits"
        );
    }
    // And the file is a scenario that runs.
    let (code, _, err) = entrynav(&[
        "trade",
        "--scenario",
        out.to_str().unwrap(),
        "--filters",
        "ekf",
        "--runs",
        "2",
        "--quiet",
    ]);
    assert_eq!(code, 0, "{err}");
}
