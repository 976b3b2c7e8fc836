//! Ctrl-C (SIGINT) during a long study: the first SIGINT sets a flag that the core's Monte Carlo
//! loop reads between runs (`McOptions::cancel`); the study stops starting runs, folds the ones
//! finished and the command writes a partial summary (`complete: false`) and exits with 130. A
//! second SIGINT kills the process as usual.
//!
//! The handler is installed with `libc::signal` directly (the `ctrlc` crate is not vendored in
//! this workspace); it only stores to an atomic and restores the default action, both
//! async-signal-safe.

use std::sync::atomic::{AtomicBool, Ordering};

/// Set by SIGINT.
pub static CANCEL: AtomicBool = AtomicBool::new(false);

/// Exit code of a command stopped by SIGINT (128 + 2, as shells report it).
pub const EXIT_INTERRUPTED: i32 = 130;

/// The error a command returns after writing its partial results on SIGINT.
#[derive(Debug)]
pub struct Interrupted(pub String);

impl std::fmt::Display for Interrupted {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "interrupted: {}", self.0)
    }
}

impl std::error::Error for Interrupted {}

extern "C" fn on_sigint(_: libc::c_int) {
    CANCEL.store(true, Ordering::SeqCst);
    // SAFETY: `signal` is async-signal-safe; SIG_DFL makes a second Ctrl-C terminate at once.
    unsafe {
        libc::signal(libc::SIGINT, libc::SIG_DFL);
    }
}

/// Install the SIGINT handler and return the flag it sets.
pub fn install() -> &'static AtomicBool {
    let handler: extern "C" fn(libc::c_int) = on_sigint;
    // SAFETY: the handler only touches an atomic and calls `signal`, both async-signal-safe.
    unsafe {
        libc::signal(libc::SIGINT, handler as libc::sighandler_t);
    }
    &CANCEL
}
