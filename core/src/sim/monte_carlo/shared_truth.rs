//! Work the runs of a Monte Carlo share when their truth realisation is the same.
//!
//! Many studies disperse only the measurement noise (seed 000's 5000 runs: the truth and the
//! filter start are Table 1's), so every run flies the same truth trajectory and has the same
//! PCRLB contribution. [`SharedTruth`] integrates the trajectory of one run's realisation once
//! and forms that run's PCRLB contribution once; every run whose realisation equals it follows
//! the stored trajectory ([`TruthSensors::with_draw_replaying`](crate::sim::engine::TruthSensors::with_draw_replaying))
//! and, when its truth samples and measurement pattern equal it too, takes the stored
//! contribution. Both are the values the run would compute itself (the same operations on the
//! same numbers), so a study's results are bit-identical with or without the sharing; a run
//! whose realisation differs (dispersed initial state, vehicle, atmosphere) computes its own.

use crate::scenario::{Scenario, TruthDraw};
use crate::sensors::MeasurementEpoch;
use crate::sim::bounds::pcrlb::{BoundRun, bound_run};
use crate::sim::engine::{
    RecordedRun, RunError, TruthPropagator, TruthSample, TruthStep, record_run,
    record_run_following,
};
use std::sync::Arc;

/// One realisation's trajectory and PCRLB contribution, for the runs that share it.
#[derive(Debug, Clone)]
pub struct SharedTruth {
    /// The realisation the trajectory and bound belong to.
    draw: TruthDraw,
    /// Every integration step at the scenario's bank; `None` when the integration failed (the
    /// runs then integrate, and report the failure, themselves).
    steps: Option<Arc<[TruthStep]>>,
    /// The PCRLB contribution and what it was computed from.
    bound: Option<SharedBound>,
}

/// A run's PCRLB contribution depends on its realisation, its truth samples and which channels
/// it measured at which times ([`bound_run`]): those, and the contribution.
#[derive(Debug, Clone)]
struct SharedBound {
    samples: Vec<TruthSample>,
    pattern: Vec<(f64, Vec<bool>)>,
    bound: Arc<BoundRun>,
}

/// Which channels an epoch measured, at its time.
fn pattern(epochs: &[MeasurementEpoch]) -> Vec<(f64, Vec<bool>)> {
    epochs
        .iter()
        .map(|e| (e.t, e.values.iter().map(Option::is_some).collect()))
        .collect()
}

/// Whether `epochs` measured the channels of `pattern` at its times (without building the
/// run's own pattern: this runs once per Monte Carlo run).
fn same_pattern(epochs: &[MeasurementEpoch], pattern: &[(f64, Vec<bool>)]) -> bool {
    epochs.len() == pattern.len()
        && epochs.iter().zip(pattern).all(|(e, (t, seen))| {
            e.t == *t
                && e.values.len() == seen.len()
                && e.values.iter().zip(seen).all(|(v, s)| v.is_some() == *s)
        })
}

impl SharedTruth {
    /// From run `run` of a study with master seed `seed`: its realisation's trajectory and, with
    /// `pcrlb`, its PCRLB contribution. `None` when that run's truth cannot be simulated: the
    /// runs then compute their own, and the failing run reports its error where it stands.
    pub fn new(scenario: &Scenario, seed: u64, run: usize, pcrlb: bool) -> Option<Self> {
        let rec = record_run(scenario, seed, run).ok()?;
        let steps = trajectory(scenario, &rec.draw).map(Arc::from);
        let bound = pcrlb.then(|| SharedBound {
            samples: rec.truth.samples.clone(),
            pattern: pattern(&rec.truth.epochs),
            bound: Arc::new(bound_run(scenario, &rec)),
        });
        Some(SharedTruth {
            draw: rec.draw,
            steps,
            bound,
        })
    }

    /// The stored trajectory, if it is `draw`'s.
    pub fn trajectory_for(&self, draw: &TruthDraw) -> Option<Arc<[TruthStep]>> {
        (*draw == self.draw).then(|| self.steps.clone()).flatten()
    }

    /// The PCRLB contribution of `rec`: the stored one when `rec` is the same realisation with
    /// the same truth samples and measurement pattern, computed otherwise.
    pub fn bound_for(&self, scenario: &Scenario, rec: &RecordedRun) -> Arc<BoundRun> {
        match &self.bound {
            Some(b)
                if rec.draw == self.draw
                    && rec.truth.samples == b.samples
                    && same_pattern(&rec.truth.epochs, &b.pattern) =>
            {
                Arc::clone(&b.bound)
            }
            _ => Arc::new(bound_run(scenario, rec)),
        }
    }
}

/// [`record_run`], following `shared`'s trajectory when the run's realisation is the one it
/// was integrated for: the same record.
pub fn record_run_sharing(
    scenario: &Scenario,
    seed: u64,
    run: usize,
    shared: Option<&SharedTruth>,
) -> Result<RecordedRun, RunError> {
    record_run_following(scenario, seed, run, |draw| {
        shared.and_then(|s| s.trajectory_for(draw))
    })
}

/// Every truth integration step of `draw` at the scenario's bank, until the truth stops; `None`
/// if a step fails.
fn trajectory(scenario: &Scenario, draw: &TruthDraw) -> Option<Vec<TruthStep>> {
    let mut propagator = TruthPropagator::for_scenario(scenario, draw.initial);
    let mut steps = Vec::with_capacity(propagator.max_steps());
    while let Some(step) = propagator.step(&draw.model, scenario.truth_bank).ok()? {
        steps.push(step);
    }
    Some(steps)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scenario::{Scenario, ScenarioConfig};

    fn scenario(name: &str) -> Scenario {
        Scenario::build(
            ScenarioConfig::builtin(name).unwrap(),
            &crate::files::no_files,
        )
        .unwrap()
    }

    /// A shared realisation gives every run the record and bound it computes alone, and a
    /// dispersed one is not taken for another run's.
    #[test]
    fn sharing_changes_no_record_and_no_bound() {
        let s = scenario("four-beacon-fusion");
        let shared = SharedTruth::new(&s, 7, 0, true).unwrap();
        for run in [1, 2, 5] {
            let alone = record_run(&s, 7, run).unwrap();
            let with = record_run_sharing(&s, 7, run, Some(&shared)).unwrap();
            assert!(shared.trajectory_for(&alone.draw).is_some(), "run {run}");
            assert_eq!(alone.truth.samples, with.truth.samples);
            assert_eq!(alone.truth.epochs, with.truth.epochs, "the noise too");
            assert_eq!(alone.x0, with.x0);
            let (b_alone, b_shared) = (bound_run(&s, &alone), shared.bound_for(&s, &with));
            assert_eq!(b_alone, *b_shared);
        }
        // A run that missed one channel at one epoch does not take the stored bound.
        let rec = record_run(&s, 7, 1).unwrap();
        let stored = pattern(&rec.truth.epochs);
        assert!(same_pattern(&rec.truth.epochs, &stored));
        let mut missed = rec.truth.epochs.clone();
        missed[3].values[0] = None;
        assert!(!same_pattern(&missed, &stored));
        // A scenario that disperses its truth: no run shares run 0's realisation.
        let d = scenario("msl-pressure");
        let shared = SharedTruth::new(&d, 7, 0, false).unwrap();
        let other = record_run(&d, 7, 1).unwrap();
        assert!(shared.trajectory_for(&other.draw).is_none());
    }
}
