//! The Monte Carlo trade study: dispersions, truth, measurements and every filter of a trade, per
//! run, folded into per-filter statistics.
//!
//! Reproducibility (the nyx-space pattern): run `i` draws everything — truth dispersions,
//! atmosphere perturbation, measurement noise, filter start — from one generator seeded by
//! `run_seed(seed, i)`, so a run does not depend on which thread executes it. Runs execute in
//! fixed-size chunks in parallel (rayon) and their records are folded into the accumulators in
//! run-index order, so 1 or N threads give bit-identical statistics, and memory is bounded by the
//! chunk size, not the number of runs.
//!
//! * [`study`] — [`run_trade`], [`run_shard`], [`run_study`], [`resume_shard`]: the entry points,
//!   with [`McOptions`] ([`options`]) in and a [`TradeReport`] ([`trade_report`]) or a
//!   [`ShardResult`] out, or a [`TradeError`] ([`trade_error`]);
//! * `blocks.rs` — the loop over accumulation blocks (parallel chunks, checkpoints, cancellation,
//!   resumption); `one_run.rs` — one run: its truth, every filter over it, its PCRLB
//!   contribution;
//! * [`shared_truth`] — the trajectory and bound the runs of one realisation share;
//! * [`run_record`] — what one filter records over a run (an engine
//!   [`Observer`](crate::sim::engine::Observer)); [`exclusions`] — its beacon exclusions judged
//!   against the truth's faults;
//! * [`metrics`], [`moments`], [`consistency`], [`gate_stats`] — the sums of a filter's runs,
//!   folded in run order; [`report`] — the summary they give ([`FilterReport`]);
//! * [`shard`] — a study split into blocks that run apart and merge exactly; [`checkpoint`] —
//!   where a running study's partial results go;
//! * [`mod@state_names`] — the names of the filter states, the columns of every table;
//! * [`replay`] — one run replayed in full; [`tuning`] — the recorded runs `tune` evaluates
//!   tunings on.

mod blocks;
pub mod checkpoint;
pub mod consistency;
pub mod exclusions;
pub mod gate_stats;
pub mod metrics;
pub mod moments;
mod one_run;
pub mod options;
pub mod replay;
pub mod report;
pub mod run_record;
pub mod shard;
pub mod shared_truth;
pub mod state_names;
pub mod study;
pub mod trade_error;
pub mod trade_report;
pub mod tuning;

pub use checkpoint::{Checkpoint, NoCheckpoint};
pub use consistency::nees_bounds_95;
pub use options::McOptions;
pub use report::{Ellipse, FilterReport, Series};
pub use run_record::filter_run;
pub use shard::{ACCUMULATION_BLOCK, Shard, ShardResult, fold_partial, merge_shards};
pub use state_names::state_names;
pub use study::{resume_shard, run_shard, run_study, run_trade};
pub use trade_error::TradeError;
pub use trade_report::TradeReport;
