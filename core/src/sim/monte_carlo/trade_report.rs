//! [`TradeReport`]: a trade study's results, every filter's summary and the scenario's PCRLB.

use super::report::FilterReport;
use crate::sim::bounds::pcrlb_sums::PcrlbReport;
use serde::Serialize;

/// A trade study's results.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TradeReport {
    /// Scenario name.
    pub scenario: String,
    /// Runs asked for.
    pub runs: usize,
    /// Whether every run asked for is in the statistics (`false` after a cancellation).
    pub complete: bool,
    /// Runs in the statistics: runs 0..runs_completed, folded exactly as a study of
    /// `runs_completed` runs would fold them.
    pub runs_completed: usize,
    /// Master seed.
    pub seed: u64,
    /// State names of the filter model, in state order (SI units in the suffix).
    pub states: Vec<String>,
    /// Measurement channel names, in epoch-slot order.
    pub channels: Vec<String>,
    /// One report per filter, in the order asked.
    pub filters: Vec<FilterReport>,
    /// The scenario's posterior Cramér–Rao lower bound ([`crate::sim::bounds::pcrlb`]); `None` for a study
    /// merged from shards written before the bound existed.
    pub pcrlb: Option<PcrlbReport>,
    /// The truth atmosphere file, its profile count and the run → profile rule, when the truth
    /// atmosphere is a table file (`--atmosphere-file`, a scenario `model = "table"`).
    pub atmosphere: Option<crate::atmosphere::ProfileProvenance>,
}
