//! Checkpoints of `entrynav trade`: while a study runs, its resumable partial summary
//! (`complete: false`, with the `resume` block and its checksum) is written atomically to the
//! `--json` path before the first run and then every `--checkpoint-every` seconds, so a study
//! killed outright (SIGKILL, power loss, an OOM kill) loses at most that much work and
//! `trade --resume FILE` continues it. The file a study starts from therefore never looks
//! current: an old `complete: true` summary at the path is replaced before the first run.

use crate::provenance::Provenance;
use crate::trade_files::write_summary;
use entrynav::sim::monte_carlo::shard::fold_partial;
use entrynav::sim::{Checkpoint, ShardResult};
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

/// The default interval (s): a study over a minute long is checkpointed; writing a summary
/// takes milliseconds, so the cost is negligible.
pub const DEFAULT_EVERY_S: f64 = 60.0;

/// The interval's allowed range (s), besides 0 (off).
pub const EVERY_RANGE_S: (f64, f64) = (0.1, 86_400.0);

/// Check `--checkpoint-every`: 0 (off) or within [`EVERY_RANGE_S`].
pub fn check_every(seconds: f64) -> Result<(), crate::exit::Usage> {
    let (lo, hi) = EVERY_RANGE_S;
    if seconds == 0.0 || (lo..=hi).contains(&seconds) {
        Ok(())
    } else {
        Err(crate::exit::Usage(format!(
            "--checkpoint-every {seconds}: must be 0 (no checkpoints) or between {lo} and {hi} s"
        )))
    }
}

/// Writes a study's partial summaries to its `--json` file.
pub struct SummaryCheckpoints {
    path: PathBuf,
    every: Duration,
    provenance: Provenance,
    started: Instant,
    last: Option<Instant>,
    /// Announce each checkpoint on standard error (with `ENTRYNAV_PROGRESS=lines`).
    announce: bool,
    warned: bool,
}

impl SummaryCheckpoints {
    /// Checkpoints to `path` every `every_s` seconds (> 0), the first before the first run.
    pub fn new(path: &Path, every_s: f64, provenance: Provenance) -> SummaryCheckpoints {
        SummaryCheckpoints {
            path: path.to_path_buf(),
            every: Duration::from_secs_f64(every_s),
            provenance,
            started: Instant::now(),
            last: None,
            announce: std::env::var_os(crate::progress::ENV).is_some_and(|v| v == "lines"),
            warned: false,
        }
    }

    fn write(&self, partial: &ShardResult) -> anyhow::Result<usize> {
        let report = fold_partial(partial.clone())?;
        let elapsed = self.started.elapsed().as_secs_f64();
        write_summary(
            &self.path,
            &self.provenance,
            &report,
            Some(partial),
            elapsed,
        )?;
        Ok(report.runs_completed)
    }
}

impl Checkpoint for SummaryCheckpoints {
    fn due(&mut self) -> bool {
        self.last.is_none_or(|t| t.elapsed() >= self.every)
    }

    fn save(&mut self, partial: &ShardResult) {
        self.last = Some(Instant::now());
        match self.write(partial) {
            Ok(runs) if self.announce => {
                eprintln!("checkpoint: {runs} runs in {}", self.path.display());
            }
            Ok(_) => {}
            // The runs are still in memory and the final write will be attempted (and its
            // failure reported with exit code 1): warn once, keep running.
            Err(e) if !self.warned => {
                self.warned = true;
                eprintln!("warning: checkpoint not written, the study goes on: {e:#}");
            }
            Err(_) => {}
        }
    }
}
