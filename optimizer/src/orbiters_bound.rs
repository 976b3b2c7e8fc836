//! Relay orbiters placed on the bound: `optimize orbiters --objective pcrlb`.
//!
//! The geometric objectives of [`crate::orbiters`] (seed 002 eq. 57, 62, or ∫ log det) score
//! the range directions alone. This problem minimises what the mission cares about: the **final
//! position PCRLB** \[m\] of the whole scenario with the candidate orbiters
//! ([`entrynav::sim::pcrlb_study`]: the filter's prior, the truth dynamics, the IMU and the
//! ranges to the orbiters with their true noise, epochs and line of sight — the bound `trade`
//! reports), on run 0 of seed [`PCRLB_SEED`](crate::ground::PCRLB_SEED) (common random numbers for every candidate, so the
//! cost is a smooth function of the elements).
//!
//! **Search.** One bound costs a few milliseconds, so the proxy's global search (about 10⁵
//! evaluations) is out of reach. The problem first solves the cheap proxy (the scenario's default
//! geometric objective) with its global search, then polishes that optimum on
//! `log10(final position PCRLB)` by the restarted Nelder–Mead of [`crate::search::polish_from`].
//! Hidden orbiters simply give no information, so no visibility penalty is needed. The answer
//! is a local optimum of the bound near the proxy's optimum, never worse than the proxy's.

use crate::error::OptimizerError;
use crate::ground::final_bound::final_position_bound_of;
use crate::orbiters::OrbitElements;
use crate::orbiters::problem::OrbiterProblem;
use crate::orbiters::solution::OrbiterSolution;
use crate::output::{BeaconNoise, orbiter_beacons};
use crate::progress::Progress;
use crate::search::polish_from;
use crate::search_options::{SearchOptions, SearchResult};
use entrynav::scenario::ScenarioConfig;
use std::time::Instant;

/// Default polish of the bound: simplex 2 % of each angle's range, 60 iterations per round.
pub fn default_bound_polish(seed: u64) -> SearchOptions {
    SearchOptions {
        seed,
        starts: 1,
        particles: 2,
        iterations: 0,
        polish_iterations: 60,
        polish_step: 0.02,
    }
}

/// The orbiter problem with the final position PCRLB as its objective.
#[derive(Debug, Clone)]
pub struct OrbiterBoundProblem {
    proxy: OrbiterProblem,
    base: ScenarioConfig,
    noise: BeaconNoise,
}

/// The bound-optimal constellation, with the proxy optimum it started from.
#[derive(Debug, Clone)]
pub struct OrbiterBoundSolution {
    /// The proxy's optimum (its objective, search and elements).
    pub proxy: OrbiterSolution,
    /// Final position PCRLB at the proxy's optimum \[m\].
    pub proxy_bound_m: f64,
    /// Canonical elements after the polish on the bound.
    pub elements: Vec<OrbitElements>,
    /// Final position PCRLB at `elements` \[m\].
    pub bound_m: f64,
    /// The polish's statistics (cost = log10 of the bound in metres).
    pub search: SearchResult,
    /// Wall time of the proxy search and the polish \[s\].
    pub elapsed_s: f64,
}

impl OrbiterBoundProblem {
    /// `proxy` on the trajectory of `base`; candidates replace the beacons of `base` by
    /// orbiters with range noise `noise` at the proxy's altitude.
    pub fn new(proxy: OrbiterProblem, base: ScenarioConfig, noise: BeaconNoise) -> Self {
        OrbiterBoundProblem { proxy, base, noise }
    }

    /// The geometric proxy problem.
    pub fn proxy(&self) -> &OrbiterProblem {
        &self.proxy
    }

    /// Final position PCRLB \[m\] of the scenario with orbiters `elements`.
    pub fn final_position_bound(&self, elements: &[OrbitElements]) -> Result<f64, OptimizerError> {
        if elements.len() != self.proxy.count() {
            return Err(OptimizerError::InvalidInput(format!(
                "{} orbit(s) given for a {}-orbiter problem",
                elements.len(),
                self.proxy.count()
            )));
        }
        let mut cfg = self.base.clone();
        cfg.beacons = orbiter_beacons(elements, self.proxy.altitude_m(), &self.noise);
        final_position_bound_of(cfg)
    }

    /// The polish cost at `x = [Ω₁, i₁, f₁, …]`: log10 of the bound in metres (non-finite when the
    /// bound cannot be formed; the search replaces it by a large finite cost).
    pub fn cost(&self, x: &[f64]) -> f64 {
        self.final_position_bound(&self.proxy.elements_from(x))
            .map_or(f64::NAN, |b| b.max(1e-300).log10())
    }

    /// Proxy search (`proxy_opts`), then the polish on the bound (`polish_opts`).
    pub fn optimize(
        &self,
        proxy_opts: &SearchOptions,
        polish_opts: &SearchOptions,
        progress: Progress<'_>,
    ) -> Result<OrbiterBoundSolution, OptimizerError> {
        let started = Instant::now();
        let proxy = self.proxy.optimize(proxy_opts, progress)?;
        let proxy_bound_m = self.final_position_bound(&proxy.elements)?;
        let x0: Vec<f64> = proxy
            .elements
            .iter()
            .flat_map(|e| [e.raan, e.inc, e.true_anomaly])
            .collect();
        let (lower, upper) = self.proxy.bounds();
        let cost = |x: &[f64]| self.cost(x);
        let search = polish_from(&cost, &x0, &lower, &upper, polish_opts, progress)?;
        let elements: Vec<OrbitElements> = self
            .proxy
            .elements_from(&search.x)
            .iter()
            .map(OrbitElements::canonical)
            .collect();
        let bound_m = self.final_position_bound(&elements)?;
        Ok(OrbiterBoundSolution {
            proxy,
            proxy_bound_m,
            elements,
            bound_m,
            search,
            elapsed_s: started.elapsed().as_secs_f64(),
        })
    }
}
