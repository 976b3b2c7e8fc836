//! Drive a navigation filter over one truth run.

use crate::estimation::nav::setup::estimation_error;
use crate::estimation::nav::{NavFilter, StepInfo, truth_in_filter_coords};
use crate::scenario::{Scenario, TruthDraw};
use crate::sim::TruthRun;
use nalgebra::{SMatrix, SVector};
use std::time::Instant;

/// The filter's state after one measurement epoch, with the truth it is judged against.
#[derive(Debug, Clone)]
pub struct NavStep<const N: usize> {
    /// Epoch time \[s\].
    pub t: f64,
    /// Posterior estimate.
    pub x: SVector<f64, N>,
    /// Posterior covariance.
    pub p: SMatrix<f64, N, N>,
    /// Truth in filter coordinates (NaN where a state has no truth counterpart).
    pub truth: SVector<f64, N>,
    /// Estimation error x̂ − x (angles wrapped).
    pub err: SVector<f64, N>,
    /// What the update reported.
    pub info: StepInfo,
    /// Filter's density at its own estimate x̂, if it estimates density [kg/m³].
    pub density_est: Option<f64>,
    /// Filter's density profile evaluated at the *true* altitude [kg/m³] (seed 001 eq. 70).
    pub density_profile_est: Option<f64>,
    /// True density at the epoch [kg/m³].
    pub density_true: f64,
    /// Planet-relative spherical truth `[r, lon, lat, v, fpa, heading]`.
    pub truth_spherical: [f64; 6],
}

impl<const N: usize> NavStep<N> {
    /// NEES eᵀP⁻¹e over the states that have a truth value, with its degrees of freedom (`None`
    /// when no state has a truth value or that block of P is not positive definite).
    pub fn nees(&self) -> Option<(f64, usize)> {
        let idx: Vec<usize> = (0..N).filter(|&i| self.truth[i].is_finite()).collect();
        if idx.len() == N {
            let chol = self.p.cholesky()?;
            let v = chol.solve(&self.err);
            return Some((self.err.dot(&v), N));
        }
        let m = idx.len();
        if m == 0 {
            return None;
        }
        let p = nalgebra::DMatrix::from_fn(m, m, |a, b| self.p[(idx[a], idx[b])]);
        let e = nalgebra::DVector::from_fn(m, |a, _| self.err[idx[a]]);
        let chol = p.cholesky()?;
        Some((e.dot(&chol.solve(&e)), m))
    }
}

/// How a filter run ended.
#[derive(Debug, Clone, PartialEq)]
pub enum FilterOutcome {
    /// Processed every epoch.
    Completed,
    /// Stopped on a numerical failure at `t` (the run reports it; nothing panicked).
    Failed {
        /// Time of the failure \[s\].
        t: f64,
        /// What failed.
        reason: String,
    },
}

/// Result of driving a filter: outcome, steps processed and CPU time spent in the filter.
#[derive(Debug, Clone)]
pub struct FilterRunSummary {
    /// How it ended.
    pub outcome: FilterOutcome,
    /// Epochs processed.
    pub steps: usize,
    /// Wall time spent inside predict + update \[ns\] (not part of reproducible results).
    pub filter_ns: u128,
}

/// Run `filter` over `run` (the truth realisation `draw`), calling `sink` after each epoch's update.
pub fn run_filter<const N: usize>(
    scenario: &Scenario,
    draw: &TruthDraw,
    run: &TruthRun,
    filter: &mut dyn NavFilter<N>,
    mut sink: impl FnMut(&NavStep<N>),
) -> FilterRunSummary {
    let mut samples = run.samples.iter().peekable();
    let mut filter_ns = 0u128;
    let mut steps = 0;
    for epoch in &run.epochs {
        while samples.peek().is_some_and(|s| s.t < epoch.t - 1e-9) {
            samples.next();
        }
        let Some(sample) = samples.peek() else { break };
        let beacons = scenario.beacon_states(epoch.t);
        let clock = Instant::now();
        let result = filter
            .predict(epoch.t)
            .and_then(|_| filter.update(epoch, &beacons));
        filter_ns += clock.elapsed().as_nanos();
        let info = match result {
            Ok(info) => info,
            Err(e) => {
                return FilterRunSummary {
                    outcome: FilterOutcome::Failed {
                        t: epoch.t,
                        reason: e.to_string(),
                    },
                    steps,
                    filter_ns,
                };
            }
        };
        let (x, p) = filter.estimate();
        if x.iter().chain(p.iter()).any(|v| !v.is_finite()) {
            return FilterRunSummary {
                outcome: FilterOutcome::Failed {
                    t: epoch.t,
                    reason: "estimate or covariance became non-finite".into(),
                },
                steps,
                filter_ns,
            };
        }
        steps += 1;
        let truth = truth_in_filter_coords::<N>(scenario, draw, sample);
        let err = estimation_error(scenario, &x, &truth);
        sink(&NavStep {
            t: epoch.t,
            x,
            p,
            truth,
            err,
            info,
            density_est: filter.density_estimate(),
            density_profile_est: filter.density_profile(sample.altitude),
            density_true: sample.density,
            truth_spherical: sample.spherical,
        });
    }
    FilterRunSummary {
        outcome: FilterOutcome::Completed,
        steps,
        filter_ns,
    }
}
