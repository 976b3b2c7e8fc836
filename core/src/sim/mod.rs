//! Simulation: the one engine (truth, sensors and a navigation filter, step by step), the batch
//! truth run, judging a filter against the truth, and the Monte Carlo studies built on them.
//!
//! * [`engine`] — the engine's step and the three step-wise simulators the FMUs wrap
//!   ([`TruthSensors`](engine::TruthSensors), [`Navigator`](engine::Navigator),
//!   [`EntryCoSim`](engine::EntryCoSim));
//! * [`record`] — [`simulate_truth`]: a whole truth run recorded (a loop over the engine), and
//!   [`record_run`]: Monte Carlo run k's truth and filter start, which filters then fly
//!   ([`Navigator::fly`](engine::Navigator::fly), the engine's one loop);
//! * [`run_record`] — what one filter records over a run (an [`engine::Observer`]);
//! * [`judge`] — the estimate beside the truth (error, NEES, deployment error);
//! * [`start`] — a run's initial estimate (nominal, or drawn around the truth);
//! * [`monte_carlo`], [`shard`], [`metrics`], [`moments`], [`report`] — trade studies: runs in
//!   parallel, folded in run order, shardable, summarised;
//! * [`pcrlb`], [`pcrlb_sums`] — the posterior Cramér–Rao lower bound of the scenario, from the
//!   same truth runs, in every trade summary;
//! * [`lincov_entry`] — LinCov of the EKF along the nominal trajectory (`entrynav lincov`);
//! * [`density_eval`] — seed 001's density RMSPE (eq. 70) over a Monte Carlo;
//! * [`training`] — seed 001 Algorithm 1's training trajectories and the whole offline training;
//! * [`guided_flight`], [`guided_run`], [`delivery`] — entry guidance flown with perfect
//!   navigation, with a filter in the loop, and the Monte Carlo of delivery at deployment;
//!   [`guided_loop`] is the filter-in-the-loop flight one truth step at a time (the guided FMU's).

pub mod checkpoint;
pub mod consistency;
pub mod delivery;
pub mod delivery_shard;
pub mod density_eval;
pub mod engine;
pub mod gate_stats;
pub mod guided_flight;
pub mod guided_loop;
pub mod guided_run;
pub mod judge;
pub mod lincov_entry;
pub mod metrics;
pub mod moments;
pub mod monte_carlo;
pub mod nominal_bound;
pub mod pcrlb;
mod pcrlb_epochs;
pub mod pcrlb_sums;
pub mod record;
pub mod replay;
pub mod report;
pub mod run_record;
pub mod shard;
pub mod shared_truth;
pub mod start;
pub mod training;
pub mod tuning;

pub use checkpoint::{Checkpoint, NoCheckpoint};
pub use engine::{SimError, StopReason, TruthSample};
pub use metrics::nees_bounds_95;
pub use monte_carlo::{
    McOptions, TradeError, TradeReport, resume_shard, run_shard, run_study, run_trade, state_names,
};
pub use pcrlb::NoBound;
pub use pcrlb_sums::{PcrlbReport, pcrlb_study};
pub use record::{
    Peak, Peaks, RecordedRun, RunError, TruthRun, channel_names, is_radio, record_run,
    simulate_truth, simulate_truth_with_peaks,
};
pub use report::{Ellipse, FilterReport, Series};
pub use shard::{Shard, ShardResult, merge_shards};

/// Seed of run `run` of a Monte Carlo with master seed `seed` (SplitMix64 of both), so every run's
/// randomness is fixed by (seed, run) alone, whatever the thread count or scheduling.
pub fn run_seed(seed: u64, run: u64) -> u64 {
    let mut z = seed
        ^ run
            .wrapping_mul(0x9E37_79B9_7F4A_7C15)
            .wrapping_add(0x632B_E59B_D9B4_E019);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}
