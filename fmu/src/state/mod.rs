//! FMU state snapshots and their byte format.
//!
//! A snapshot is a *replay log*: the parameters and inputs, the experiment set-up, the phase, and
//! every successful `fmi2DoStep` so far with the inputs it used. Restoring rebuilds the engine and
//! replays the steps; because the engine is deterministic this reproduces the rest of the run bit
//! for bit.
//!
//! Byte format (little-endian), version [`FORMAT_VERSION`]:
//! `b"ENAVFMUS"`, `u32` version, `u64` total length, `u8` model, `u32`+bytes GUID, `u8` phase,
//! `f64` start time, `u8`+`f64` stop time, `u32` count + tagged values (tag 0 none, 1 real `f64`,
//! 2 integer `i32`, 3 boolean `u8`, 4 string `u32`+UTF-8), `u32` inputs per step, `u64` step count
//! and per step `f64` t, `f64` h, `u8` 0 (the inputs of the previous step) or 1 followed by the
//! tagged input values, then an FNV-1a 64 checksum of everything before it. Every length is
//! checked against the remaining bytes before use, and a state is at most
//! [`crate::limits::MAX_STATE_BYTES`] long.
//!
//! In memory the log is a [`StepLog`]: steps whose inputs did not change share them, and full
//! chunks of steps are shared between the instance and the snapshots taken from it, so holding
//! many FMU states of a long run costs little.

use crate::limits::MAX_STATE_BYTES;
use crate::vars::{Model, Value};
use thiserror::Error;

/// Why serialized FMU-state bytes cannot be restored.
#[derive(Debug, Error, Clone, PartialEq, Eq)]
pub enum StateError {
    /// Not written by this FMU.
    #[error("not an entrynav FMU state (bad magic bytes)")]
    BadMagic,
    /// Another format version.
    #[error(
        "FMU state format version {0} is not supported (this FMU reads version {FORMAT_VERSION})"
    )]
    Version(u32),
    /// The header's length is not the buffer's.
    #[error("FMU state length mismatch: header says {header} bytes, got {actual}")]
    Length {
        /// Length in the header.
        header: u64,
        /// Bytes given.
        actual: usize,
    },
    /// The checksum does not match.
    #[error("FMU state checksum mismatch (corrupted bytes)")]
    Checksum,
    /// The bytes end early.
    #[error("FMU state is truncated")]
    Truncated,
    /// Bytes left after the last field.
    #[error("FMU state has {0} trailing bytes")]
    Trailing(usize),
    /// An unknown value tag.
    #[error("FMU state has an unknown value tag {0}")]
    ValueTag(u8),
    /// A field that cannot be valid.
    #[error("FMU state {0}")]
    Corrupt(&'static str),
    /// More bytes than a state may have.
    #[error("FMU state of {0} bytes is larger than the {MAX_STATE_BYTES} bytes a state may have")]
    TooLarge(usize),
}

/// Magic bytes.
pub const MAGIC: &[u8; 8] = b"ENAVFMUS";
/// Format version (2: steps may share the previous step's inputs).
pub const FORMAT_VERSION: u32 = 2;

/// Where the instance was in the FMI state machine.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Phase {
    /// After fmi2Instantiate / fmi2Reset.
    Instantiated,
    /// Between fmi2EnterInitializationMode and fmi2ExitInitializationMode.
    InitializationMode,
    /// Ready for fmi2DoStep.
    StepComplete,
    /// After fmi2Terminate.
    Terminated,
    /// After an error that needs fmi2Reset, fmi2SetFMUstate or fmi2FreeInstance.
    Error,
}

impl Phase {
    /// Every phase, in the order of the FMI 2.0 state machine.
    pub const ALL: [Phase; 5] = [
        Phase::Instantiated,
        Phase::InitializationMode,
        Phase::StepComplete,
        Phase::Terminated,
        Phase::Error,
    ];

    /// Its code in the state byte format (and its bit in [`crate::instance::Phases`]).
    pub(crate) const fn code(self) -> u8 {
        match self {
            Phase::Instantiated => 0,
            Phase::InitializationMode => 1,
            Phase::StepComplete => 2,
            Phase::Terminated => 3,
            Phase::Error => 4,
        }
    }

    pub(super) fn from_code(c: u8) -> Option<Phase> {
        Some(match c {
            0 => Phase::Instantiated,
            1 => Phase::InitializationMode,
            2 => Phase::StepComplete,
            3 => Phase::Terminated,
            4 => Phase::Error,
            _ => return None,
        })
    }
}

/// A saved FMU state.
#[derive(Debug, Clone, PartialEq)]
pub struct Snapshot {
    /// Model.
    pub model: Model,
    /// GUID of the model's table when saved.
    pub guid: String,
    /// Phase.
    pub phase: Phase,
    /// Experiment start time.
    pub start_time: f64,
    /// Experiment stop time, if defined.
    pub stop_time: Option<f64>,
    /// Current value of every variable that has one stored (parameters, inputs), in table order.
    pub values: Vec<Option<Value>>,
    /// Steps so far.
    pub steps: StepLog,
}

mod bytes;
mod log;

pub use log::{StepLog, StepRecord};
