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
//!
//! When standard error is not a terminal (a log file, a batch job, CI) and neither applies, a
//! timed line replaces the invisible bar every [`INTERVAL_ENV`] seconds (default 5):
//!
//! ```text
//! progress: 640/5000 runs (12.8 %) after 8.3 s, eta 56.7 s
//! ```

use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// The environment variable that sets the timed lines' interval in seconds (default 5).
pub const INTERVAL_ENV: &str = "ENTRYNAV_PROGRESS_INTERVAL_S";

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
    /// A line every `every` while standard error is not a terminal.
    Timed {
        /// Runs asked for.
        total: usize,
        /// When the study started.
        start: Instant,
        /// When the last line was written.
        last: Mutex<Instant>,
        /// Interval between lines.
        every: Duration,
    },
}

fn interval() -> Duration {
    let s = std::env::var(INTERVAL_ENV)
        .ok()
        .and_then(|v| v.trim().parse::<f64>().ok())
        .filter(|s| s.is_finite() && (0.01..=3600.0).contains(s))
        .unwrap_or(5.0);
    Duration::from_secs_f64(s)
}

impl RunProgress {
    /// The progress of a study of `total` runs labelled `message`; `--quiet` shows none, even
    /// with `ENTRYNAV_PROGRESS=lines`.
    pub fn new(total: usize, quiet: bool, message: String) -> RunProgress {
        let lines = std::env::var_os(ENV).is_some_and(|v| v == "lines");
        match (quiet, lines) {
            (true, _) => RunProgress::Bar(ProgressBar::hidden()),
            (false, true) => RunProgress::Lines { total },
            (false, false) if !std::io::stderr().is_terminal() => {
                let start = Instant::now();
                RunProgress::Timed {
                    total,
                    start,
                    last: Mutex::new(start),
                    every: interval(),
                }
            }
            (false, false) => RunProgress::Bar(bar(total, message)),
        }
    }

    /// `done` runs have finished.
    pub fn set(&self, done: usize) {
        match self {
            RunProgress::Bar(b) => b.set_position(done as u64),
            RunProgress::Lines { total } => eprintln!("{}", line(done, *total)),
            RunProgress::Timed {
                total,
                start,
                last,
                every,
            } => {
                let now = Instant::now();
                let Ok(mut last) = last.lock() else { return };
                if now.duration_since(*last) >= *every && done < *total {
                    *last = now;
                    eprintln!("{}", timed_line(done, *total, now.duration_since(*start)));
                }
            }
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

/// One timed progress line.
fn timed_line(done: usize, total: usize, elapsed: Duration) -> String {
    let s = elapsed.as_secs_f64();
    let eta = if done > 0 {
        format!(
            "{:.1} s",
            s * (total - done.min(total)) as f64 / done as f64
        )
    } else {
        "unknown".into()
    };
    format!(
        "progress: {done}/{total} runs ({:.1} %) after {s:.1} s, eta {eta}",
        100.0 * done as f64 / total.max(1) as f64
    )
}

/// One progress line.
fn line(done: usize, total: usize) -> String {
    format!("progress: {done}/{total} runs")
}
