//! The bounds of every option a front end passes to a study, checked here once so that the
//! command line and the Python package refuse the same value with the same message before any
//! work starts: `runs = 0 is out of range: must be from 1 to 10000000`.
//!
//! Front ends hand over what the user typed as wide integers (`i128`) or `f64`, so that a negative
//! or huge value reaches this check instead of failing in a type conversion with a message that
//! names no option. The bounds follow from what one machine does in reasonable time and memory:
//! ten million Monte Carlo runs bound the work of one study, 1024 worker threads bound the pool
//! (far above any core count a study benefits from; a pool of a million threads is what
//! `threads=10**6` would otherwise start).

use entrynav::estimation::nav::FilterKind;
use std::fmt;

/// Largest Monte Carlo run count of a study (`runs`, `validation_runs`, `check_runs`).
pub const MAX_RUNS: usize = 10_000_000;

/// Largest worker-thread count.
pub const MAX_THREADS: usize = 1024;

/// An option outside its range: names the option, the value and what is allowed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{option} = {value} {problem}: must be {allowed}")]
pub struct OptionError {
    /// The option's name (the Python keyword; the command-line flag without `--`, `_` for `-`).
    pub option: String,
    /// The value given, as text.
    pub value: String,
    /// What is wrong with it: "is out of range" (a number), "is unknown" (a name).
    pub problem: &'static str,
    /// What is allowed ("from 1 to 10000000", "at least 1", "one of ekf, ukf").
    pub allowed: String,
}

impl OptionError {
    /// The number `option = value` is not `allowed`.
    pub fn new(option: &str, value: impl fmt::Display, allowed: impl Into<String>) -> OptionError {
        OptionError {
            option: option.to_string(),
            value: value.to_string(),
            problem: "is out of range",
            allowed: allowed.into(),
        }
    }

    /// The name `option = 'value'` is not one of `allowed`.
    pub fn unknown(option: &str, value: &str, allowed: impl Into<String>) -> OptionError {
        OptionError {
            option: option.to_string(),
            value: format!("'{}'", shorten(value)),
            problem: "is unknown",
            allowed: allowed.into(),
        }
    }
}

/// A value as a message quotes it: at most 60 characters (a 10 000-character name does not
/// flood the terminal).
pub fn shorten(value: &str) -> String {
    if value.chars().count() <= 60 {
        return value.to_string();
    }
    let head: String = value.chars().take(50).collect();
    format!("{head}… ({} characters)", value.chars().count())
}

/// Longest name a written scenario may be given (`scenario_name`): it heads reports and tables.
pub const MAX_NAME_CHARS: usize = 200;

/// A name (`scenario_name`): 1 to [`MAX_NAME_CHARS`] characters, none of them a control
/// character.
pub fn name(option: &str, value: &str) -> Result<(), OptionError> {
    let n = value.chars().count();
    if n == 0 || n > MAX_NAME_CHARS || value.chars().any(char::is_control) {
        return Err(OptionError {
            option: option.to_string(),
            value: format!("'{}'", shorten(value)),
            problem: "is not a usable name",
            allowed: format!("1 to {MAX_NAME_CHARS} characters without control characters"),
        });
    }
    Ok(())
}

/// One filter name of option `option` (`check_filter = 'x' is unknown: must be one of ekf, …`).
pub fn filter(option: &str, name: &str) -> Result<FilterKind, OptionError> {
    FilterKind::parse(name).map_err(|_| {
        let valid: Vec<&str> = FilterKind::ALL.iter().map(|k| k.name()).collect();
        OptionError::unknown(option, name, format!("one of {}", valid.join(", ")))
    })
}

/// A comma-separated list of filter names of option `option` (as the scenario-level parser reads
/// it: empty entries skipped, a repeated name kept once), at least one.
pub fn filter_list(option: &str, list: &str) -> Result<Vec<FilterKind>, OptionError> {
    let mut kinds = Vec::new();
    for name in list.split(',').filter(|n| !n.trim().is_empty()) {
        let kind = filter(option, name)?;
        if !kinds.contains(&kind) {
            kinds.push(kind);
        }
    }
    if kinds.is_empty() {
        return Err(filter(option, list).unwrap_err());
    }
    Ok(kinds)
}

/// A whole number `value` of option `option` in `lo..=hi`.
pub fn count(option: &str, value: i128, lo: usize, hi: usize) -> Result<usize, OptionError> {
    if value < lo as i128 || value > hi as i128 {
        return Err(OptionError::new(
            option,
            value,
            format!("from {lo} to {hi}"),
        ));
    }
    Ok(value as usize)
}

/// A Monte Carlo run count: 1 to [`MAX_RUNS`].
pub fn runs(option: &str, value: i128) -> Result<usize, OptionError> {
    count(option, value, 1, MAX_RUNS)
}

/// A worker-thread count: 1 to [`MAX_THREADS`]; `None` is every core.
pub fn threads(value: Option<i128>) -> Result<Option<usize>, OptionError> {
    value
        .map(|n| count("threads", n, 1, MAX_THREADS))
        .transpose()
}

/// A master seed: 0 to 2^64 - 1.
pub fn seed(option: &str, value: i128) -> Result<u64, OptionError> {
    if value < 0 || value > u64::MAX as i128 {
        return Err(OptionError::new(
            option,
            value,
            format!("from 0 to {}", u64::MAX),
        ));
    }
    Ok(value as u64)
}

/// A finite real `value` of option `option` in `lo..=hi`.
pub fn real(option: &str, value: f64, lo: f64, hi: f64) -> Result<f64, OptionError> {
    if !(value.is_finite() && value >= lo && value <= hi) {
        return Err(OptionError::new(
            option,
            number(value),
            format!("a number from {} to {}", number(lo), number(hi)),
        ));
    }
    Ok(value)
}

/// Finest trajectory sample step of a design \[s\]: a design evaluates every candidate along the
/// whole entry at every sample, so 0.01 s over a 400 s entry (40 000 samples) is minutes of
/// search; finer steps do not end in reasonable time.
pub const MIN_SAMPLE_STEP_S: f64 = 0.01;

/// A trajectory sample step `step` of option `option` on an entry of `duration_s` seconds: from
/// [`MIN_SAMPLE_STEP_S`] to half the entry (at least two samples).
pub fn sample_step(option: &str, step: f64, duration_s: f64) -> Result<f64, OptionError> {
    real(option, step, MIN_SAMPLE_STEP_S, duration_s / 2.0)
}

/// An angle `value` \[deg\] of option `option` in `lo..=hi`.
pub fn degrees(option: &str, value: f64, lo: f64, hi: f64) -> Result<f64, OptionError> {
    real(option, value, lo, hi)
}

/// A real number as a person reads it: plain from 1e-4 up to 1e15, else in scientific notation
/// (`1e300`, not three hundred digits).
pub fn number(v: f64) -> String {
    if v == 0.0 || !v.is_finite() || (1e-4..1e15).contains(&v.abs()) {
        format!("{v}")
    } else {
        format!("{v:e}")
    }
}

/// Check an already-typed count (a Rust caller's options struct) against `lo..=hi`.
pub fn check_count(option: &str, value: usize, lo: usize, hi: usize) -> Result<(), OptionError> {
    count(option, value as i128, lo, hi).map(|_| ())
}

/// Check an already-typed thread count.
pub fn check_threads(value: Option<usize>) -> Result<(), OptionError> {
    threads(value.map(|n| n as i128)).map(|_| ())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_bound_names_the_option_the_value_and_the_range() {
        assert_eq!(
            runs("runs", 0).unwrap_err().to_string(),
            "runs = 0 is out of range: must be from 1 to 10000000"
        );
        assert_eq!(runs("runs", 10_000_000), Ok(10_000_000));
        assert_eq!(
            threads(Some(1_000_000)).unwrap_err().to_string(),
            "threads = 1000000 is out of range: must be from 1 to 1024"
        );
        assert_eq!(
            threads(Some(-1)).unwrap_err().to_string(),
            "threads = -1 is out of range: must be from 1 to 1024"
        );
        assert_eq!(threads(None), Ok(None));
        assert!(
            seed("seed", -1)
                .unwrap_err()
                .to_string()
                .starts_with("seed = -1")
        );
        assert_eq!(seed("seed", u64::MAX as i128), Ok(u64::MAX));
        assert!(real("step", f64::NAN, 0.1, 10.0).is_err());
        assert_eq!(real("step", 1.0, 0.1, 10.0), Ok(1.0));
        assert_eq!(
            real("time_limit", 1e300, 0.0, 1e6).unwrap_err().to_string(),
            "time_limit = 1e300 is out of range: must be a number from 0 to 1000000"
        );
        assert!(
            filter_list("filters", "ekf,0")
                .unwrap_err()
                .to_string()
                .starts_with("filters = '0' is unknown: must be one of ekf, ukf, ci")
        );
        assert_eq!(
            filter_list("filters", "ekf, ukf"),
            Ok(vec![FilterKind::Ekf, FilterKind::Ukf])
        );
        assert_eq!(
            filter_list("filters", "ekf,,ekf"),
            Ok(vec![FilterKind::Ekf])
        );
        assert!(filter_list("filters", " , ").is_err());
    }
}
