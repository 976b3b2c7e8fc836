//! The exit code of a failed command, and the CLI's own two kinds of error (a study's error says
//! its kind itself: `entrynav_studies::ErrorKind`).
//!
//! | code | meaning |
//! |---|---|
//! | 0 | success |
//! | 1 | a runtime failure: a truth simulation that fails during a study, an error while writing results |
//! | 2 | a usage or configuration error: bad arguments (clap), a scenario, override, grid or filter list that does not load or validate, an output path that cannot be written — anything refused before the work starts |
//! | 130 | interrupted by SIGINT (partial results written where the command supports it) |

use crate::interrupt::{EXIT_INTERRUPTED, Interrupted};
use entrynav_studies::{ErrorKind, StudyError};

/// A usage or configuration error found by the CLI itself (exit code 2).
#[derive(Debug)]
pub struct Usage(pub String);

impl std::fmt::Display for Usage {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Usage {}

/// A failure while doing the work (exit code 1), as opposed to refusing it.
#[derive(Debug)]
pub struct Runtime(pub String);

impl std::fmt::Display for Runtime {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.0)
    }
}

impl std::error::Error for Runtime {}

/// The exit code of a command that failed with `e`: 130 interrupted, 1 for a runtime failure
/// (a [`Runtime`] error, a truth simulation failing inside a study), 2 for everything refused up
/// front.
pub fn code(e: &anyhow::Error) -> i32 {
    if e.downcast_ref::<Interrupted>().is_some() {
        return EXIT_INTERRUPTED;
    }
    // A study's error says itself which of the three it is.
    if let Some(kind) = e
        .chain()
        .find_map(|c| c.downcast_ref::<StudyError>())
        .map(StudyError::kind)
    {
        return match kind {
            ErrorKind::Refused => 2,
            ErrorKind::Failed => 1,
            ErrorKind::Interrupted => EXIT_INTERRUPTED,
        };
    }
    let runtime = e.chain().any(|c| {
        c.is::<Runtime>()
            || c.is::<entrynav_studies::output::atomic_file::OutputError>()
            || c.is::<entrynav::sim::SimError>()
            || matches!(
                c.downcast_ref::<entrynav::sim::TradeError>(),
                Some(entrynav::sim::TradeError::Truth(_))
            )
    });
    if runtime { 1 } else { 2 }
}
