//! Bounds on everything an importer or a scenario file can make the FMU size or do.
//!
//! Every count, length, size or interval that comes from outside (the master's arguments, the
//! parameters and inputs, a serialized FMU state, a scenario file) is checked against one of these
//! constants *before* it sizes an allocation or a loop. A request over a bound is answered with
//! `fmi2Error` and a logged reason naming the bound, and changes nothing; it never reaches an
//! allocator that would abort the process.
//!
//! | what | bound |
//! |---|---|
//! | value references in one fmi2Get*/fmi2Set* call (fmi2Get/SetString) | [`MAX_VALUE_REFS`] ([`MAX_STRING_REFS`]) |
//! | bytes of a String value, instance name, log category | [`MAX_STRING_BYTES`] |
//! | bytes of the fmuGUID / fmuResourceLocation | [`MAX_GUID_BYTES`] / [`MAX_LOCATION_BYTES`] |
//! | categories in one fmi2SetDebugLogging | [`MAX_CATEGORIES`] |
//! | bytes of a serialized FMU state (and of the replay log it holds) | [`MAX_STATE_BYTES`] |
//! | FMU states held by one instance | [`MAX_SNAPSHOTS`] |
//! | bytes of a scenario file / of a file it refers to | [`MAX_SCENARIO_BYTES`] / [`MAX_TABLE_BYTES`] |
//! | beacons, channels, model-bank members of a scenario | [`MAX_SCENARIO_BEACONS`], [`MAX_SCENARIO_CHANNELS`], [`MAX_BANK_MODELS`] |
//! | truth RK4 steps of one run (duration / truth step) | [`MAX_RUN_TRUTH_STEPS`] |
//! | filter sub-steps of one prediction of the filter FMU | [`MAX_PREDICTION_SUBSTEPS`] |
//!
//! The work of one fmi2DoStep is therefore bounded: the truth advances at most
//! [`MAX_RUN_TRUTH_STEPS`] RK4 steps over a whole run (it stops at the scenario duration), the
//! combined engine is advanced in chunks of [`STEP_CHUNK_TRUTH_STEPS`] so the epochs of one step
//! are never collected all at once, and the filter FMU refuses an epoch whose prediction would
//! need more than [`MAX_PREDICTION_SUBSTEPS`] sub-steps, or that lies after the scenario's duration.

use entrynav::scenario::Scenario;
use thiserror::Error;

/// Value references in one fmi2Get*/fmi2Set* call (a table has about 200 variables).
pub const MAX_VALUE_REFS: usize = 65_536;
/// Value references in one fmi2GetString or fmi2SetString call: each value is a copy of a string of up to
/// [`MAX_STRING_BYTES`], so at most 4 MiB are copied per call.
pub const MAX_STRING_REFS: usize = 1024;
/// Bytes of one String value, the instance name or a log category name.
pub const MAX_STRING_BYTES: usize = 4096;
/// Bytes of the fmuGUID argument.
pub const MAX_GUID_BYTES: usize = 256;
/// Bytes of the fmuResourceLocation argument (a percent-encoded path).
pub const MAX_LOCATION_BYTES: usize = 16_384;
/// The largest Monte Carlo run index the guided FMU's `run` parameter accepts.
pub const MAX_RUN: i32 = 999_999_999;
/// Log categories in one fmi2SetDebugLogging call.
pub const MAX_CATEGORIES: usize = 64;
/// Bytes of a serialized FMU state; an instance stops recording its replay log (and
/// fmi2GetFMUstate refuses) once the state would exceed it. (In memory a log takes up to about
/// 5.5 times its serialized size: ~90 MiB for the filter FMU, whose 37 inputs may all change at
/// every step; a 400 s run in 0.01 s steps needs 9 MiB.)
pub const MAX_STATE_BYTES: usize = 16 << 20;
/// FMU states one instance holds at a time.
pub const MAX_SNAPSHOTS: usize = 256;
/// Bytes of a scenario file.
pub const MAX_SCENARIO_BYTES: u64 = 1 << 20;
/// Bytes of a file a scenario refers to (a tabulated atmosphere).
pub const MAX_TABLE_BYTES: u64 = 16 << 20;
/// Beacons of a scenario.
pub const MAX_SCENARIO_BEACONS: usize = 64;
/// Measurement channels of a scenario.
pub const MAX_SCENARIO_CHANNELS: usize = 512;
/// Members of a model bank (mmae, mmae-moe).
pub const MAX_BANK_MODELS: usize = 64;
/// Truth RK4 steps of one run: `duration_s / truth_step_s` (the built-in scenarios need at most
/// 7,000).
pub const MAX_RUN_TRUTH_STEPS: usize = 1_000_000;
/// RK4 sub-steps of one filter prediction of the filter FMU (the core refuses the same number:
/// about 0.2 s of EKF work).
pub const MAX_PREDICTION_SUBSTEPS: usize = 100_000;
/// Truth steps per engine call inside one fmi2DoStep of the combined FMU.
pub const STEP_CHUNK_TRUTH_STEPS: usize = 10_000;

/// A request or a scenario over one of the bounds.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum LimitError {
    /// A count or a length over its bound.
    #[error("{what} is {got}; the limit is {max}")]
    TooMany {
        /// What was counted.
        what: &'static str,
        /// The count asked for.
        got: u64,
        /// The bound.
        max: u64,
    },
    /// A scenario whose run needs more truth steps than a run may take.
    #[error(
        "the scenario needs {steps} truth steps (duration {duration} s / truth step {step} s); an FMU run may take at most {MAX_RUN_TRUTH_STEPS}"
    )]
    RunTooLong {
        /// Truth steps of the run.
        steps: f64,
        /// `timing.duration_s`.
        duration: f64,
        /// `timing.truth_step_s`.
        step: f64,
    },
    /// A filter prediction over more sub-steps than one doStep may take.
    #[error(
        "the measurement epoch at t = {epoch} s is {gap} s after the last one processed (t = {last} s): predicting to it needs {substeps} sub-steps of at most {step} s, more than the {MAX_PREDICTION_SUBSTEPS} one fmi2DoStep may take"
    )]
    Prediction {
        /// The epoch asked for \[s\].
        epoch: f64,
        /// The last epoch processed \[s\].
        last: f64,
        /// `epoch - last` \[s\].
        gap: f64,
        /// Sub-steps the prediction needs.
        substeps: f64,
        /// The filter's sub-step \[s\].
        step: f64,
    },
    /// A measurement epoch the truth can never produce.
    #[error(
        "the measurement epoch at t = {epoch} s is after the scenario's duration ({duration} s)"
    )]
    EpochAfterDuration {
        /// The epoch asked for \[s\].
        epoch: f64,
        /// `timing.duration_s`.
        duration: f64,
    },
}

/// `got` against `max` for `what`.
pub fn at_most(what: &'static str, got: usize, max: usize) -> Result<(), LimitError> {
    if got > max {
        return Err(LimitError::TooMany {
            what,
            got: got as u64,
            max: max as u64,
        });
    }
    Ok(())
}

/// Check a scenario against the structural and work bounds before an engine is built on it.
pub fn check_scenario(s: &Scenario) -> Result<(), LimitError> {
    at_most(
        "the number of beacons",
        s.beacons.len(),
        MAX_SCENARIO_BEACONS,
    )?;
    at_most(
        "the number of measurement channels",
        s.channels.len(),
        MAX_SCENARIO_CHANNELS,
    )?;
    at_most(
        "the number of model-bank members (filter.model_bank_density_bias)",
        s.onboard.tuning.model_bank_density_bias.len(),
        MAX_BANK_MODELS,
    )?;
    let t = &s.config.timing;
    let steps = (t.duration_s / t.truth_step_s).round();
    if !(steps.is_finite() && steps <= MAX_RUN_TRUTH_STEPS as f64) {
        return Err(LimitError::RunTooLong {
            steps,
            duration: t.duration_s,
            step: t.truth_step_s,
        });
    }
    Ok(())
}

/// Check that a filter prediction from the epoch `last` to `epoch` with sub-steps of at most
/// `step` stays within [`MAX_PREDICTION_SUBSTEPS`] (counted without the core's rounding slack,
/// so a prediction this check lets through is never refused by the core) and that `epoch` is
/// within the scenario's `duration`.
pub fn check_prediction(last: f64, epoch: f64, step: f64, duration: f64) -> Result<(), LimitError> {
    let gap = epoch - last;
    let substeps = (gap / step).ceil();
    if !(substeps.is_finite() && substeps <= MAX_PREDICTION_SUBSTEPS as f64) {
        return Err(LimitError::Prediction {
            epoch,
            last,
            gap,
            substeps,
            step,
        });
    }
    if epoch > duration * (1.0 + 1e-9) {
        return Err(LimitError::EpochAfterDuration { epoch, duration });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn predictions_and_counts() {
        assert!(check_prediction(0.0, 1.0, 1.0, 300.0).is_ok());
        assert!(check_prediction(0.0, 300.0, 1.0, 300.0).is_ok());
        let e = check_prediction(0.0, 1e9, 1.0, 300.0).unwrap_err();
        assert!(matches!(e, LimitError::Prediction { .. }), "{e}");
        assert!(e.to_string().contains("100000"), "{e}");
        let e = check_prediction(0.0, 1e18, 1.0, 300.0).unwrap_err();
        assert!(matches!(e, LimitError::Prediction { .. }), "{e}");
        let e = check_prediction(250.0, 301.0, 1.0, 300.0).unwrap_err();
        assert!(matches!(e, LimitError::EpochAfterDuration { .. }), "{e}");
        assert!(check_prediction(0.0, f64::MAX, 1e-300, f64::MAX).is_err());
        assert!(at_most("x", 3, 3).is_ok());
        assert!(
            at_most("x", 4, 3)
                .unwrap_err()
                .to_string()
                .contains("limit is 3")
        );
    }
}
