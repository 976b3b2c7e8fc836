//! `entrynav tune` with several filters (issue "Beacon designs that navigate better, and say
//! so"): each filter gets its own Q in `[filter.tuned.<name>]`, the written file keeps the user's
//! comments and layout, and a trade of it on seeds the tuning never saw has every filter
//! consistent and no worse than the input.

mod common;

use common::{entrynav, scratch_dir};
use serde_json::Value;
use std::path::Path;

/// ground-beacons-3 with a process noise 10⁶–10⁸ times too large (both filters under-confident:
/// ANEES/dof ≈ 0.45) and a comment of the user's.
fn mistuned_input(dir: &Path) -> std::path::PathBuf {
    let (code, text, err) = entrynav(&["scenario", "show", "ground-beacons-3"]);
    assert_eq!(code, 0, "{err}");
    let shared = "q_diag = [1.78e-5, 1.78e-17, 1.78e-17, 1.78e-7, 3.16e-18, 3.16e-18]";
    assert!(text.contains(shared), "the built-in's Q changed: {text}");
    let text = text.replace(
        shared,
        "# my note: deliberately large Q, keep me\nq_diag = [1.0e2, 1.0e-10, 1.0e-10, 1.0e0, 1.0e-10, 1.0e-10]",
    );
    let path = dir.join("input.toml");
    std::fs::write(&path, text).unwrap();
    path
}

fn tune(input: &Path, filters: &str, out: &Path) -> String {
    let (code, stdout, err) = entrynav(&[
        "tune",
        "--scenario",
        input.to_str().unwrap(),
        "--filter",
        filters,
        "--out",
        out.to_str().unwrap(),
        "--quiet",
        "--threads",
        "2",
    ]);
    assert_eq!(code, 0, "{stdout}\n{err}");
    stdout
}

/// The per-filter JSON blocks of a 100-run trade on seed 7 (not the tuning's 1 or validation's).
fn trade(scenario: &Path, filters: &str) -> Vec<Value> {
    common::trade_filters(scenario, filters, 100, 7, &scenario.with_extension("json"))
}

fn num(f: &Value, path: &[&str]) -> f64 {
    let mut v = f;
    for p in path {
        v = &v[*p];
    }
    v.as_f64()
        .unwrap_or_else(|| panic!("{path:?} missing in {f}"))
}

#[test]
fn each_filter_gets_its_own_q_and_the_file_keeps_the_users_text() {
    let dir = scratch_dir("tune", "per_filter");
    let input = mistuned_input(&dir);
    let out = dir.join("T.toml");
    let stdout = tune(&input, "ekf,ukf", &out);
    let text = std::fs::read_to_string(&out).unwrap();
    let original = std::fs::read_to_string(&input).unwrap();

    // The user's text survives: every line of the input is in the output, in order.
    let mut rest = text.as_str();
    for line in original.lines() {
        let at = rest
            .find(line)
            .unwrap_or_else(|| panic!("input line lost or reordered: {line:?}\n{text}"));
        rest = &rest[at + line.len()..];
    }
    // One table per filter, with different Q (tuned separately), numbers at six digits.
    for name in ["ekf", "ukf"] {
        assert_eq!(
            text.matches(&format!("[filter.tuned.{name}]")).count(),
            1,
            "{text}"
        );
        assert!(
            text.contains(&format!("# {name}: its own tuning")),
            "{text}"
        );
    }
    let q_of = |name: &str| -> Vec<String> {
        let table = text
            .split(&format!("[filter.tuned.{name}]"))
            .nth(1)
            .unwrap();
        let body = table.split("q_diag = [").nth(1).unwrap();
        body.split(']')
            .next()
            .unwrap()
            .split(',')
            .map(|v| v.trim().to_string())
            .filter(|v| !v.is_empty())
            .collect()
    };
    let (qe, qu) = (q_of("ekf"), q_of("ukf"));
    assert_eq!((qe.len(), qu.len()), (6, 6));
    // Tuned separately: different Q, unless both searches ended at the same search bound
    // (ground-beacons-3's truth flies no process noise, so Q → 0 is each filter's optimum).
    let at_bound = stdout
        .lines()
        .filter(|l| l.trim_start().starts_with("q["))
        .all(|l| l.contains("(at the search bound)"));
    assert!(qe != qu || at_bound, "one Q served both filters\n{stdout}");
    for v in qe.iter().chain(&qu) {
        let mantissa = v.split(['e', 'E']).next().unwrap();
        let digits: String = mantissa.chars().filter(char::is_ascii_digit).collect();
        assert!(digits.trim_start_matches('0').len() <= 6, "{v}");
    }

    // On fresh seeds every tuned filter is consistent and no worse than the input.
    let before = trade(&input, "ekf,ukf");
    let after = trade(&out, "ekf,ukf");
    for (b, a) in before.iter().zip(&after) {
        let name = a["name"].as_str().unwrap();
        let anees = num(a, &["anees"]) / num(a, &["nees_dof"]);
        assert!((0.7..=1.5).contains(&anees), "{name}: ANEES/dof {anees}");
        let band = |f: &Value| num(f, &["nees_in_bounds_frac"]);
        assert!(
            band(a) >= 0.9 * band(b),
            "{name}: band {} -> {}",
            band(b),
            band(a)
        );
        for key in ["rmse_time_avg", "rmse_final"] {
            let (rb, ra) = (num(b, &[key, "pos_m"]), num(a, &[key, "pos_m"]));
            assert!(ra <= 1.1 * rb, "{name}: {key} {rb} -> {ra}");
        }
    }
}

#[test]
fn tuning_one_filter_leaves_the_others_untouched_and_a_kept_tuning_changes_nothing() {
    let dir = scratch_dir("tune", "one_filter");
    let input = mistuned_input(&dir);
    let out = dir.join("U.toml");
    tune(&input, "ukf", &out);
    let text = std::fs::read_to_string(&out).unwrap();
    assert!(text.contains("[filter.tuned.ukf]") && !text.contains("[filter.tuned.ekf]"));
    // The EKF flies exactly as before; the UKF does not.
    let before = trade(&input, "ekf,ukf");
    let after = trade(&out, "ekf,ukf");
    assert_eq!(
        before[0], after[0],
        "the EKF changed although only the UKF was tuned"
    );
    assert_ne!(before[1]["anees"], after[1]["anees"]);
    // Tuning the tuned UKF again: it is consistent now, the file is written unchanged.
    let again = dir.join("U2.toml");
    let stdout = tune(&out, "ukf", &again);
    assert!(stdout.contains("already consistent"), "{stdout}");
    assert_eq!(std::fs::read_to_string(&again).unwrap(), text);
}
