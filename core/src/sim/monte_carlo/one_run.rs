//! One Monte Carlo run of a trade: its truth recorded, every filter flown over it, and its PCRLB
//! contribution.

use super::run_record::{RunRecord, filter_run};
use super::shared_truth::{SharedTruth, record_run_sharing};
use super::trade_error::TradeError;
use crate::estimation::nav::FilterKind;
use crate::scenario::Scenario;
use crate::sim::bounds::pcrlb::{BoundRun, bound_run};
use std::sync::Arc;

/// One run's records (one per filter) and, when asked, its PCRLB contribution.
pub(super) type RunWithBound = (Vec<RunRecord>, Option<Arc<BoundRun>>);

/// One run: the truth recorded, each filter flown over it and, with `pcrlb`, the run's
/// contribution to the scenario's PCRLB ([`crate::sim::bounds::pcrlb`]). A run of `shared`'s
/// realisation takes its trajectory and bound instead of computing them again ([`SharedTruth`]).
pub(super) fn one_run_with_bound(
    scenario: &Arc<Scenario>,
    filters: &[FilterKind],
    seed: u64,
    run: usize,
    pcrlb: bool,
    shared: Option<&SharedTruth>,
) -> Result<RunWithBound, TradeError> {
    let rec = record_run_sharing(scenario, seed, run, shared)?;
    let bound = pcrlb.then(|| match shared {
        Some(s) => s.bound_for(scenario, &rec),
        None => Arc::new(bound_run(scenario, &rec)),
    });
    let records = filters
        .iter()
        .map(|&kind| filter_run(scenario, &scenario.onboard, &rec, kind))
        .collect();
    Ok((records, bound))
}
