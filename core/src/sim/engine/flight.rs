//! The engine's loop over a recorded truth run: [`Navigator::fly`] feeds a filter every
//! measurement epoch of the run, stops it on a numerical failure, judges its estimate against the
//! truth at each epoch and hands the result to an [`Observer`]. It owns the loop as argmin's
//! `Executor` owns an optimiser's: the Monte Carlo, the replay of one run, the density
//! evaluation and `entrynav tune` only say what to keep (each is an [`Observer`]), so the order
//! "process, check failure, judge, record" is written once.

use super::filter::{FilterFailure, Judgement};
use super::navigator::{NavStatus, Navigator};
use super::record::RecordedRun;
use super::truth::TruthSample;
use crate::scenario::Scenario;
use crate::sensors::MeasurementEpoch;
use std::time::Instant;

/// What a consumer of a flight keeps. The engine calls [`Observer::epoch`] after every epoch the
/// filter processed without failure, in time order, and [`Observer::failure`] at most once, when
/// the filter stops (no epoch follows it).
pub trait Observer {
    /// The filter processed `epoch`; `judgement` is its estimate against the truth `sample`
    /// (the navigator holds the estimate, σ and the update's report).
    fn epoch(
        &mut self,
        nav: &Navigator,
        epoch: &MeasurementEpoch,
        sample: &TruthSample,
        judgement: Judgement,
    );

    /// The filter stopped on a numerical failure at `t`.
    fn failure(&mut self, _t: f64, _reason: &FilterFailure) {}
}

/// How a flight ended.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct FlightEnd {
    /// Epochs processed and judged (the failed one excluded).
    pub steps: usize,
    /// Wall-clock time spent in the filter's steps \[ns\] (not reproducible; for timing only).
    pub filter_ns: u128,
    /// The numerical failure that stopped the filter, if any: (time, what).
    pub failure: Option<(f64, FilterFailure)>,
}

impl Navigator {
    /// Fly the recorded run `run` of `scenario`: process its measurement epochs in order, stop
    /// at a numerical failure, judge each processed epoch against the run's truth and report it
    /// to `observer`. The navigator keeps its final state.
    pub fn fly<O: Observer + ?Sized>(
        &mut self,
        scenario: &Scenario,
        run: &RecordedRun,
        observer: &mut O,
    ) -> FlightEnd {
        let mut end = FlightEnd::default();
        for (epoch, sample) in run.truth.epochs_with_truth() {
            let clock = Instant::now();
            self.process(epoch);
            end.filter_ns += clock.elapsed().as_nanos();
            if let NavStatus::Failed { t, reason } = self.status() {
                observer.failure(*t, reason);
                end.failure = Some((*t, reason.clone()));
                return end;
            }
            end.steps += 1;
            let judgement = self.judge(scenario, &run.draw, sample);
            observer.epoch(self, epoch, sample, judgement);
        }
        end
    }
}
