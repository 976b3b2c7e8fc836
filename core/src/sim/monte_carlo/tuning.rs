//! The Monte Carlo behind filter tuning: a set of runs recorded once (truth, measurement epochs,
//! initial estimate) over which any re-tuned filter is evaluated again and again — common random
//! numbers, so two tunings differ only by the tuning, not by the noise they happened to see.
//!
//! An evaluation folds the runs into the same accumulators as a trade study, in run order, so its
//! consistency numbers are what `entrynav trade` prints for those runs (bit for bit up to one
//! accumulation block, 256 runs), on any thread count.

use super::metrics::FilterAccumulator;
use super::report::FilterReport;
use super::run_record::{RunRecord, filter_run};
use super::state_names::state_names;
use super::trade_error::TradeError;
use crate::estimation::Onboard;
use crate::estimation::nav::FilterKind;
use crate::scenario::Scenario;
use crate::sim::engine::{RecordedRun, channel_names, record_run};
use rayon::prelude::*;
use std::sync::Arc;

/// Runs recorded for tuning.
#[derive(Debug, Clone)]
pub struct TuningRuns {
    scenario: Arc<Scenario>,
    runs: Vec<RecordedRun>,
}

impl TuningRuns {
    /// Record runs `0..count` of a study of `scenario` with master seed `seed` (the same runs as
    /// `entrynav trade --seed SEED`).
    pub fn record(scenario: &Scenario, seed: u64, count: usize) -> Result<Self, TradeError> {
        if count == 0 {
            return Err(TradeError::Options("tuning needs at least one run".into()));
        }
        let runs = (0..count)
            .into_par_iter()
            .map(|run| record_run(scenario, seed, run))
            .collect::<Result<Vec<_>, _>>()?;
        Ok(TuningRuns {
            scenario: Arc::new(scenario.clone()),
            runs,
        })
    }

    /// The scenario the runs belong to.
    pub fn scenario(&self) -> &Arc<Scenario> {
        &self.scenario
    }

    /// Number of runs.
    pub fn len(&self) -> usize {
        self.runs.len()
    }

    /// Whether there are no runs (never, by construction).
    pub fn is_empty(&self) -> bool {
        self.runs.is_empty()
    }

    /// Filters `kinds` built from `onboard` (the scenario's, or a re-tuned copy from
    /// [`Onboard::with_tuning`]) over every recorded run: one report per filter.
    pub fn evaluate(
        &self,
        onboard: &Arc<Onboard>,
        kinds: &[FilterKind],
    ) -> Result<Vec<FilterReport>, TradeError> {
        for k in kinds {
            k.check_fits(onboard)?;
        }
        let sc = &self.scenario;
        let records: Vec<Vec<RunRecord>> = self
            .runs
            .par_iter()
            .map(|rec| {
                kinds
                    .iter()
                    .map(|&kind| filter_run(sc, onboard, rec, kind))
                    .collect()
            })
            .collect();
        let mut accs = vec![FilterAccumulator::default(); kinds.len()];
        for (rec, per_filter) in self.runs.iter().zip(&records) {
            for (acc, r) in accs.iter_mut().zip(per_filter) {
                acc.add(rec.run, r);
            }
        }
        let (states, channels) = (state_names(sc), channel_names(sc));
        Ok(kinds
            .iter()
            .zip(&accs)
            .map(|(k, a)| a.report(k.name(), &states, &channels))
            .collect())
    }
}
