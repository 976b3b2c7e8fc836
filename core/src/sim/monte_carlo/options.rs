//! [`McOptions`]: how many runs of a Monte Carlo, from which seed, in which chunks, with or
//! without the PCRLB, and the flag that cancels it.

use std::sync::atomic::{AtomicBool, Ordering};

/// Monte Carlo options.
#[derive(Debug, Clone, Copy)]
pub struct McOptions {
    /// Number of runs.
    pub runs: usize,
    /// Master seed.
    pub seed: u64,
    /// Runs per parallel chunk (memory bound; does not change results).
    pub chunk: usize,
    /// Form the scenario's PCRLB from the same truth runs ([`crate::sim::bounds::pcrlb`]; costs about one
    /// EKF's worth of work per run).
    pub pcrlb: bool,
    /// Cancellation: once this flag is set, no new run starts; the runs finished so far (the
    /// longest prefix in run order) are folded and the report says `complete: false`. The core
    /// only reads the flag; the caller sets it (the CLI from its SIGINT handler).
    pub cancel: Option<&'static AtomicBool>,
}

impl McOptions {
    /// Whether the caller has cancelled the study.
    pub(super) fn cancelled(&self) -> bool {
        self.cancel.is_some_and(|c| c.load(Ordering::Relaxed))
    }
}

impl McOptions {
    /// `runs` runs from `seed` with the default chunk of 64.
    pub fn new(runs: usize, seed: u64) -> Self {
        McOptions {
            runs,
            seed,
            chunk: 64,
            pcrlb: true,
            cancel: None,
        }
    }
}
