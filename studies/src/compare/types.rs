//! What `trade compare` finds: each input as it saw it ([`Source`]), per filter the compared
//! quantities ([`Row`]) with the χ² band of an ANEES ([`Band`]), and the whole comparison
//! ([`Comparison`]), which serialises to the JSON `trade compare --json` writes.

use crate::statistics::{Difference, Estimate};
use serde::Serialize;

/// One input file as the comparison saw it.
#[derive(Debug, Clone, Serialize)]
pub struct Source {
    /// The file.
    pub path: String,
    /// Its scenario name.
    pub scenario: String,
    /// Its `provenance.scenario_fingerprint`.
    pub scenario_fingerprint: Option<String>,
    /// Its `--set` overrides.
    pub overrides: Vec<String>,
    /// Its master seed.
    pub seed: u64,
    /// Whether the study finished.
    pub complete: bool,
}

/// One compared quantity of one filter.
#[derive(Debug, Clone, Serialize)]
pub struct Row {
    /// `rmse_time_avg`, `rmse_final`, `anees`, `anees_kinematic` or `bad_run_fraction`.
    pub metric: &'static str,
    /// State name (`pos_m`, `vel_mps` for the error norms); empty for whole-filter metrics.
    pub state: String,
    /// A and its standard error.
    pub a: Estimate,
    /// B and its standard error.
    pub b: Estimate,
    /// B − A with its 95 % interval.
    #[serde(flatten)]
    pub difference: Difference,
    /// For `rmse_final_paired`: the runs valid in both final-errors files.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub paired_runs: Option<u64>,
    /// For ANEES: the per-epoch 95 % χ² band of A and B and whether each ANEES lies inside.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub band: Option<Band>,
}

/// The χ² consistency band of an ANEES in A and B.
#[derive(Debug, Serialize, Clone, Copy)]
pub struct Band {
    /// Degrees of freedom.
    pub dof: usize,
    /// A's band.
    pub a: [f64; 2],
    /// B's band.
    pub b: [f64; 2],
    /// A's ANEES inside its band.
    pub a_inside: bool,
    /// B's ANEES inside its band.
    pub b_inside: bool,
}

/// One filter present in both summaries.
#[derive(Debug, Clone, Serialize)]
pub struct FilterComparison {
    /// Filter name.
    pub name: String,
    /// Runs used for A's and B's standard errors (runs folded minus numerical failures).
    pub runs: [u64; 2],
    /// Diverged runs in A and B (heavy tails: the intervals are then too narrow).
    pub diverged: [u64; 2],
    /// Compared quantities.
    pub rows: Vec<Row>,
}

/// The whole comparison (also the `--json` output, by `Serialize`).
#[derive(Debug, Clone, Serialize)]
pub struct Comparison {
    /// Summary A.
    pub a: Source,
    /// Summary B.
    pub b: Source,
    /// Confidence level of the intervals.
    pub confidence: f64,
    /// How the standard errors were obtained, and what the pairing of runs means.
    pub notes: Vec<String>,
    /// What differs between the two resolved scenarios (`path: A -> B`), when they differ and
    /// both summaries carry them.
    pub scenario_differences: Vec<String>,
    /// Filters in both summaries.
    pub filters: Vec<FilterComparison>,
    /// Filters only in A.
    pub only_in_a: Vec<String>,
    /// Filters only in B.
    pub only_in_b: Vec<String>,
}
