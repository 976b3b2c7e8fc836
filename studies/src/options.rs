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

use std::fmt;

/// Largest Monte Carlo run count of a study (`runs`, `validation_runs`, `check_runs`).
pub const MAX_RUNS: usize = 10_000_000;

/// Largest worker-thread count.
pub const MAX_THREADS: usize = 1024;

/// An option outside its range: names the option, the value and what is allowed.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[error("{option} = {value} is out of range: must be {allowed}")]
pub struct OptionError {
    /// The option's name (the Python keyword; the command-line flag without `--`, `_` for `-`).
    pub option: String,
    /// The value given, as text.
    pub value: String,
    /// What is allowed ("from 1 to 10000000", "at least 1", "one of ekf, ukf").
    pub allowed: String,
}

impl OptionError {
    /// `option = value` is not `allowed`.
    pub fn new(option: &str, value: impl fmt::Display, allowed: impl Into<String>) -> OptionError {
        OptionError {
            option: option.to_string(),
            value: value.to_string(),
            allowed: allowed.into(),
        }
    }
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
    }
}
