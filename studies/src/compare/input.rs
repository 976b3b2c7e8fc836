//! The part of a trade summary (`trade --json`) that `trade compare` reads, and reading it.

use crate::error::{StudyError, StudyResult};
use serde::Deserialize;
use std::collections::BTreeMap;

/// A per-state statistic as the summary holds it (`null` where undefined).
pub type Stats = BTreeMap<String, Option<f64>>;

/// The part of a trade summary a comparison reads.
#[derive(Debug, Clone, Deserialize)]
pub struct SummaryIn {
    /// Where it came from (absent in a summary of an older entrynav).
    #[serde(default)]
    pub provenance: Option<ProvenanceIn>,
    /// Scenario name.
    pub scenario: String,
    /// Master seed.
    pub seed: u64,
    /// Runs in the statistics.
    pub runs_completed: u64,
    /// Whether the study finished.
    #[serde(default = "yes")]
    pub complete: bool,
    /// Each filter's statistics.
    pub filters: Vec<FilterIn>,
}

fn yes() -> bool {
    true
}

/// The summary's `provenance` block: which scenario, which overrides.
#[derive(Debug, Clone, Deserialize)]
pub struct ProvenanceIn {
    /// The resolved scenario's fingerprint.
    pub scenario_fingerprint: Option<String>,
    /// The `--set` overrides.
    #[serde(default)]
    pub overrides: Vec<String>,
    /// The resolved scenario (written since the summaries carry it).
    #[serde(default)]
    pub scenario: Option<serde_json::Value>,
}

/// One filter's statistics (the fields of `sim::FilterReport` a comparison uses).
#[derive(Debug, Clone, Deserialize)]
pub struct FilterIn {
    /// Filter name.
    pub name: String,
    /// Runs folded.
    pub runs: u64,
    /// Runs stopped on a numerical failure.
    pub failed: u64,
    /// Runs whose final NEES exceeds 100 × dof.
    pub diverged: u64,
    /// Time-averaged RMSE per state.
    pub rmse_time_avg: Stats,
    /// Final RMSE per state.
    pub rmse_final: Stats,
    /// Mean final error per state.
    #[serde(default)]
    pub final_error_mean: Stats,
    /// Average NEES.
    pub anees: Option<f64>,
    /// Its degrees of freedom.
    pub nees_dof: usize,
    /// Its per-epoch 95 % band.
    pub nees_bounds_95: [f64; 2],
    /// Average NEES of the six kinematic states.
    pub anees_kinematic: Option<f64>,
    /// Its per-epoch 95 % band.
    pub nees_kinematic_bounds_95: [f64; 2],
}

impl SummaryIn {
    /// Read a trade summary from its text; anything else is refused saying so (the caller
    /// names the file).
    pub fn parse(text: &str) -> StudyResult<SummaryIn> {
        serde_json::from_str(text).map_err(|e| {
            StudyError::Refused(format!(
                "not a trade summary written by `trade --json` ({e})"
            ))
        })
    }
}
