//! Checkpoints of `entrynav trade`: while a study runs, its resumable partial summary
//! (`complete: false`, with the `resume` block and its checksum) is written atomically to the
//! `--json` path before the first run and then every `--checkpoint-every` seconds, so a study
//! killed outright (SIGKILL, power loss, an OOM kill) loses at most that much work and
//! `trade --resume FILE` continues it. The file a study starts from therefore never looks
//! current: an old `complete: true` summary at the path is replaced before the first run. The
//! interval's bounds and default are the study's (`entrynav_studies::trade::options`).

use crate::trade_outputs::write_text;
use entrynav::sim::{Checkpoint, ShardResult};
use entrynav_studies::provenance::Provenance;
use entrynav_studies::trade::study::partial_summary;
use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

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
        let elapsed = self.started.elapsed().as_secs_f64();
        let (text, runs) = partial_summary(&self.provenance, partial, elapsed)?;
        write_text(&self.path, &text)?;
        Ok(runs)
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
