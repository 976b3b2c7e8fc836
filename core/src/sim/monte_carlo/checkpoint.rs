//! Checkpoints of a running study: where its partial results go while it runs, so that a study
//! killed outright (SIGKILL, power loss) loses at most the runs since its last checkpoint.
//!
//! The engine decides *what* a checkpoint holds (the finished blocks and the current block's
//! sums, a `complete: false` [`ShardResult`] that [`resume_shard`](super::study::resume_shard) continues exactly); the
//! caller decides *when* ([`Checkpoint::due`]) and *where* ([`Checkpoint::save`]). The core does
//! no I/O and reads no clock.

use super::shard::ShardResult;

/// Receives a study's partial results ([`run_study`](super::study::run_study)).
pub trait Checkpoint {
    /// Whether a checkpoint is wanted now; asked once before the first run and after every chunk
    /// of runs (so at most one chunk's runs are lost beyond the caller's interval).
    fn due(&mut self) -> bool;
    /// Keep `partial`: the study so far, `complete: false`, resumable by
    /// [`resume_shard`](super::study::resume_shard).
    fn save(&mut self, partial: &ShardResult);
}

/// No checkpoints.
#[derive(Debug, Clone, Copy, Default)]
pub struct NoCheckpoint;

impl Checkpoint for NoCheckpoint {
    fn due(&mut self) -> bool {
        false
    }

    fn save(&mut self, _: &ShardResult) {}
}
