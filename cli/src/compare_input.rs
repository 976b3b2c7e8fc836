//! The part of a trade summary (`trade --json`) that `trade compare` reads, and reading it.

use crate::exit::Usage;
use anyhow::{Context, Result};
use serde::Deserialize;
use std::collections::BTreeMap;
use std::path::Path;

/// A per-state statistic as the summary holds it (`null` where undefined).
pub(crate) type Stats = BTreeMap<String, Option<f64>>;

/// The part of a trade summary a comparison reads.
#[derive(Deserialize)]
pub(crate) struct SummaryIn {
    #[serde(default)]
    pub(crate) provenance: Option<ProvenanceIn>,
    pub(crate) scenario: String,
    pub(crate) seed: u64,
    pub(crate) runs_completed: u64,
    #[serde(default = "yes")]
    pub(crate) complete: bool,
    pub(crate) filters: Vec<FilterIn>,
}

fn yes() -> bool {
    true
}

/// The summary's `provenance` block: which scenario, which overrides.
#[derive(Deserialize)]
pub(crate) struct ProvenanceIn {
    pub(crate) scenario_fingerprint: Option<String>,
    #[serde(default)]
    pub(crate) overrides: Vec<String>,
    /// The resolved scenario (written since the summaries carry it).
    #[serde(default)]
    pub(crate) scenario: Option<serde_json::Value>,
}

/// One filter's statistics (the fields of `sim::FilterReport` a comparison uses).
#[derive(Deserialize)]
pub(crate) struct FilterIn {
    pub(crate) name: String,
    pub(crate) runs: u64,
    pub(crate) failed: u64,
    pub(crate) diverged: u64,
    pub(crate) rmse_time_avg: Stats,
    pub(crate) rmse_final: Stats,
    #[serde(default)]
    pub(crate) final_error_mean: Stats,
    pub(crate) anees: Option<f64>,
    pub(crate) nees_dof: usize,
    pub(crate) nees_bounds_95: [f64; 2],
    pub(crate) anees_kinematic: Option<f64>,
    pub(crate) nees_kinematic_bounds_95: [f64; 2],
}

/// Read the trade summary `path`; anything else is a usage error (exit code 2) naming it.
pub(crate) fn read(path: &Path) -> Result<SummaryIn> {
    let usage = |m: String| Usage(format!("{}: {m}", path.display()));
    let text = entrynav_loader::read_text(path)
        .with_context(|| format!("{}: cannot read", path.display()))?;
    let summary = serde_json::from_str(&text).map_err(|e| {
        usage(format!(
            "not a trade summary written by `trade --json` ({e})"
        ))
    })?;
    Ok(summary)
}
