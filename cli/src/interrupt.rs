//! Signals: Ctrl-C (SIGINT) during a long study, and SIGPIPE on a closed output pipe, both
//! through `signal-hook`.
//!
//! The first SIGINT sets a flag that the core's Monte Carlo loop reads between runs
//! (`McOptions::cancel`); the study stops starting runs, folds the ones finished and the command
//! writes a partial summary (`complete: false`) and exits with 130. A second SIGINT runs the
//! default action at once: the process is killed by the signal, as if no handler were installed.

use std::sync::atomic::AtomicBool;
use std::sync::{Arc, OnceLock};

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

/// The flag SIGINT sets, with its handlers registered once per process.
static CANCEL: OnceLock<Arc<AtomicBool>> = OnceLock::new();

/// Install the SIGINT handlers (once per process) and return the flag they set.
///
/// Two actions run in order on each SIGINT: the default action if the flag is already set (so
/// the second Ctrl-C kills), then setting the flag (which arms the first action). Registration
/// fails only for a forbidden signal, which SIGINT is not; should it fail anyway, the flag is
/// still returned and Ctrl-C keeps its default action.
pub fn install() -> &'static AtomicBool {
    CANCEL.get_or_init(|| {
        let flag = Arc::new(AtomicBool::new(false));
        let sigint = signal_hook::consts::SIGINT;
        let registered = signal_hook::flag::register_conditional_default(sigint, flag.clone())
            .and_then(|_| signal_hook::flag::register(sigint, flag.clone()));
        if let Err(e) = registered {
            eprintln!("warning: cannot handle Ctrl-C ({e}); it will stop without partial results");
        }
        flag
    })
}

/// Let a write into a closed pipe (`entrynav simulate --out - | head -1`) end the process
/// quietly, as other Unix tools do: Rust ignores SIGPIPE, so the write would fail (and `println!`
/// panic); with the default action run on SIGPIPE the process ends instead.
pub fn die_on_broken_pipe() {
    let always = Arc::new(AtomicBool::new(true));
    if let Err(e) =
        signal_hook::flag::register_conditional_default(signal_hook::consts::SIGPIPE, always)
    {
        eprintln!("warning: cannot restore the default SIGPIPE action ({e})");
    }
}
