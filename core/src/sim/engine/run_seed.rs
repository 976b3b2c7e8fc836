//! [`run_seed`]: the seed of one Monte Carlo run, fixed by the study's master seed and the run
//! index alone.

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
