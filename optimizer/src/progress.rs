//! [`Progress`]: the callback an optimization reports its evaluations to.

/// A progress callback: `(evaluations done, evaluations budgeted)`. Called from worker threads.
pub type Progress<'a> = &'a (dyn Fn(usize, usize) + Sync);

/// A progress callback that does nothing.
pub fn no_progress(_done: usize, _total: usize) {}
