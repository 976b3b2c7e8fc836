//! The filter's initial estimate in a run: the onboard nominal start, or (Monte Carlo of seed
//! 001 §V.B) a draw around the run's truth. This needs the truth, so it lives here and not in the
//! filter: the filter only receives the vector.

use super::judge::truth_in_filter_coords;
use super::truth::TruthSample;
use crate::scenario::{Scenario, TruthDraw};
use rand::Rng;
use rand_distr::{Distribution, StandardNormal};

/// The initial estimate of one run: `filter.initial` as a fixed start (seed 000 Table 1), or,
/// with `filter.sample_initial_from_p0`, the truth at t = 0 (`t0_sample` of the realisation
/// `draw`) plus a draw from N(0, P0) using `rng` — one standard normal per state, in state order;
/// a state without a truth value is centred on its nominal start.
pub fn initial_estimate(
    scenario: &Scenario,
    draw: &TruthDraw,
    t0_sample: &TruthSample,
    rng: &mut impl Rng,
) -> Vec<f64> {
    let onboard = &scenario.onboard;
    let n = onboard.state_dim();
    let nominal = |i: usize| onboard.initial_estimate.get(i).copied().unwrap_or(0.0);
    if !scenario.config.filter.sample_initial_from_p0 {
        return (0..n).map(nominal).collect();
    }
    let p0 = |i: usize| onboard.tuning.p0_diag.get(i).copied().unwrap_or(1.0);
    let truth = truth_in_filter_coords(scenario, draw, t0_sample, n);
    (0..n)
        .map(|i| {
            let z: f64 = StandardNormal.sample(rng);
            let centre = if truth[i].is_finite() {
                truth[i]
            } else {
                nominal(i)
            };
            centre + p0(i).sqrt() * z
        })
        .collect()
}
