//! Simulation: the one engine (truth, sensors and a navigation filter, step by step), the batch
//! truth run, judging a filter against the truth, and the studies built on them, one folder per
//! role:
//!
//! * [`engine`] — the engine's step and the three step-wise simulators the FMUs wrap
//!   ([`TruthSensors`](engine::TruthSensors), [`Navigator`](engine::Navigator),
//!   [`EntryCoSim`](engine::EntryCoSim)); a whole truth run recorded ([`simulate_truth`]) and
//!   Monte Carlo run k's truth and filter start ([`record_run`], seeded by [`run_seed`]), which
//!   filters then fly ([`Navigator::fly`](engine::Navigator::fly), the engine's one loop);
//!   judging an estimate against the truth ([`engine::judge`]) and a run's initial estimate
//!   ([`engine::start`]);
//! * [`monte_carlo`] — trade studies: runs in parallel, folded in run order, shardable,
//!   checkpointed, summarised ([`run_trade`], [`TradeReport`], [`TradeError`]); the replay of one
//!   run and the recorded runs `tune` evaluates on;
//! * [`bounds`] — the posterior Cramér–Rao lower bound of the scenario, from the same truth runs,
//!   in every trade summary, and the nominal-trajectory bound of beacon design;
//! * [`lincov`] — LinCov of the EKF along the nominal trajectory (`entrynav lincov`);
//! * [`density`] — seed 001's training trajectories and offline training, and its density RMSPE
//!   (eq. 70) over a Monte Carlo;
//! * [`guided`] — entry guidance flown with perfect navigation, with a filter in the loop (one
//!   truth step at a time, the guided FMU's loop), and the Monte Carlo of delivery at deployment.

pub mod bounds;
pub mod density;
pub mod engine;
pub mod guided;
pub mod lincov;
pub mod monte_carlo;

pub use bounds::{NoBound, PcrlbReport, pcrlb_study};
pub use engine::{
    Peak, Peaks, RecordedRun, RunError, SimError, StopReason, TruthRun, TruthSample, channel_names,
    initial_estimate, is_radio, record_run, run_seed, simulate_truth, simulate_truth_with_peaks,
};
pub use monte_carlo::{
    ACCUMULATION_BLOCK, Checkpoint, Ellipse, FilterReport, McOptions, NoCheckpoint, Series, Shard,
    ShardResult, TradeError, TradeReport, filter_run, fold_partial, merge_shards, nees_bounds_95,
    resume_shard, run_shard, run_study, run_trade, state_names,
};
