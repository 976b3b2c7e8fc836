//! The bounds of the developer tools' options, checked before an FMU is opened or a step taken,
//! with the study layer's messages (`stop = 1e300 is out of range: must be a number from 0.001
//! to 100000`). How they were chosen: a run is at most [`MAX_STEPS`] communication steps (the
//! FMUs' own bound on one run's truth steps, `entrynav_fmu::limits::MAX_RUN_TRUTH_STEPS`; a
//! million rows of about 40 outputs is a 300 MB CSV); a simulated time of [`MAX_STOP_S`] is a
//! day, against minutes for any entry; the fuzzer's call count and sequence length bound its run
//! time (100 000 calls take seconds, CI's long mode is 5 000 000).

use anyhow::Result;
use entrynav_studies::options::{self, OptionError};
use std::path::Path;

/// Most communication steps of one run.
pub const MAX_STEPS: usize = entrynav_fmu::limits::MAX_RUN_TRUTH_STEPS;
/// Longest simulated time \[s\].
pub const MAX_STOP_S: f64 = 100_000.0;
/// Shortest communication step \[s\].
pub const MIN_STEP_S: f64 = 1e-6;
/// Most repetitions of the doStep benchmark.
pub const MAX_REPS: usize = 1000;
/// Most fuzzer calls.
pub const MAX_CALLS: usize = 100_000_000;
/// Longest fuzzer call sequence on one instance.
pub const MAX_SEQUENCE: usize = 10_000;

/// A stop time \[s\]: 0.001 to [`MAX_STOP_S`].
pub fn stop(value: f64) -> Result<f64, OptionError> {
    options::real("stop", value, 1e-3, MAX_STOP_S)
}

/// A communication step `value` \[s\] of a run of `duration` seconds: at most [`MAX_STEPS`]
/// steps and at most the whole run.
pub fn step(value: f64, duration: f64) -> Result<f64, OptionError> {
    let finest = (duration / MAX_STEPS as f64).max(MIN_STEP_S);
    options::real("step", value, finest, duration.max(finest))
}

/// A count `value` of option `option` in `1..=hi`.
pub fn count(option: &str, value: usize, hi: usize) -> Result<usize, OptionError> {
    options::count(option, value as i128, 1, hi)
}

/// Refuse, before it is opened, an FMU (or other input) `path` of option `option` that is not a
/// readable regular file.
pub fn input(path: &Path, option: &str) -> Result<()> {
    Ok(entrynav_studies::input::check_file(path, option)?)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_and_times_are_bounded_with_the_option_named() {
        assert_eq!(
            stop(1e300).unwrap_err().to_string(),
            "stop = 1e300 is out of range: must be a number from 0.001 to 100000"
        );
        assert!(
            step(1e-9, 300.0)
                .unwrap_err()
                .to_string()
                .starts_with("step = 1e-9")
        );
        assert_eq!(step(0.1, 300.0), Ok(0.1));
        assert!(step(301.0, 300.0).is_err());
        assert!(count("reps", 0, MAX_REPS).is_err());
    }
}
