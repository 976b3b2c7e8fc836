//! [`Stats`]: what a fuzzer run did, counted as it goes and reported at the end.

/// What the fuzzer did.
#[derive(Debug, Default)]
pub(super) struct Stats {
    pub(super) calls: usize,
    pub(super) sequences: usize,
    /// Answers by status (OK, Warning, Discard, Error, Fatal).
    pub(super) statuses: [usize; 5],
    pub(super) refused: usize,
    pub(super) failed: usize,
    /// Steps refused because their work would be over a bound (the filter FMU's prediction).
    pub(super) work_refused: usize,
    /// Steps that succeeded.
    pub(super) steps: usize,
    pub(super) huge_steps: usize,
    pub(super) tiny_steps: usize,
    pub(super) over_bound: usize,
    /// Calls whose `nValues` did not match what the references hold (FMI 3.0).
    pub(super) count_mismatches: usize,
    /// Calls naming an unknown value reference or one of another type.
    pub(super) bad_refs: usize,
    /// Calls with a null array and a non-zero count.
    pub(super) null_arrays: usize,
    /// Calls of functions of capabilities the FMU does not have (FMI 3.0).
    pub(super) unsupported: usize,
    /// Instantiations the FMU had to refuse (NULL).
    pub(super) refused_instances: usize,
    /// Array reads compared with the scalar outputs (FMI 3.0).
    pub(super) array_checks: usize,
    /// Serialised FMU states deserialised and serialised again byte for byte.
    pub(super) round_trips: usize,
    /// Calls on freed or null instances.
    pub(super) dead_calls: usize,
    pub(super) messages: usize,
}
