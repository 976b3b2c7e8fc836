//! The progress of a Monte Carlo study on standard error: an `indicatif` bar (drawn only on a
//! terminal), nothing with `--quiet`, or, with the environment variable
//! `ENTRYNAV_PROGRESS=lines`, one machine-readable line per finished chunk of runs,
//!
//! ```text
//! progress: 64/1000 runs
//! ```
//!
//! for a script or a test that drives the command through a pipe (where the bar is hidden) and
//! needs to know that runs have finished, e.g. before it sends Ctrl-C.

use indicatif::{ProgressBar, ProgressStyle};

/// The environment variable that selects line progress (`lines`).
pub const ENV: &str = "ENTRYNAV_PROGRESS";

/// How a study shows its progress.
pub enum RunProgress {
    /// A bar (hidden with `--quiet` or when standard error is not a terminal).
    Bar(ProgressBar),
    /// `progress: DONE/TOTAL runs` lines.
    Lines {
        /// Runs asked for.
        total: usize,
    },
}

impl RunProgress {
    /// The progress of a study of `total` runs labelled `message`; `--quiet` shows none, even
    /// with `ENTRYNAV_PROGRESS=lines`.
    pub fn new(total: usize, quiet: bool, message: String) -> RunProgress {
        let lines = std::env::var_os(ENV).is_some_and(|v| v == "lines");
        match (quiet, lines) {
            (true, _) => RunProgress::Bar(ProgressBar::hidden()),
            (false, true) => RunProgress::Lines { total },
            (false, false) => RunProgress::Bar(bar(total, message)),
        }
    }

    /// `done` runs have finished.
    pub fn set(&self, done: usize) {
        match self {
            RunProgress::Bar(b) => b.set_position(done as u64),
            RunProgress::Lines { total } => eprintln!("{}", line(done, *total)),
        }
    }

    /// The study is over: the bar is cleared.
    pub fn finish(&self) {
        if let RunProgress::Bar(b) = self {
            b.finish_and_clear();
        }
    }
}

fn bar(total: usize, message: String) -> ProgressBar {
    let bar = ProgressBar::new(total as u64);
    bar.set_style(
        ProgressStyle::with_template(
            "{spinner} {msg} [{bar:40}] {pos}/{len} runs ({per_sec}, eta {eta})",
        )
        .unwrap_or_else(|_| ProgressStyle::default_bar())
        .progress_chars("=> "),
    );
    bar.set_message(message);
    bar
}

/// One progress line.
fn line(done: usize, total: usize) -> String {
    format!("progress: {done}/{total} runs")
}
