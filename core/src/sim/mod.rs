//! Simulation: the truth simulator (fixed-step RK4 truth plus sensor records), the filter
//! harness, and the Monte Carlo engine with its metrics.

pub mod cosim;
pub mod metrics;
pub mod monte_carlo;
pub mod navigation;
pub mod report;
pub mod truth;

pub use metrics::nees_bounds_95;
pub use monte_carlo::{
    McOptions, Shard, ShardResult, TradeError, TradeReport, merge_shards, run_shard, run_trade,
    state_names,
};
pub use navigation::{FilterOutcome, NavStep, run_filter};
pub use report::{Ellipse, FilterReport, Series};
pub use truth::{MeasurementEpoch, SimError, StopReason, TruthRun, TruthSample, simulate_truth};

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
