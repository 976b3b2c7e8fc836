//! [`StepInfo`]: what a navigation filter reports after an update (NIS, innovations, weights,
//! what its gate did).

use super::gate_report::GateReport;

/// What a filter reports after an update.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct StepInfo {
    /// Normalised innovation squared νᵀS⁻¹ν of the measurements used (None when none were).
    pub nis: Option<f64>,
    /// Number of scalar measurements used.
    pub n_meas: usize,
    /// Innovations z − h(x̂⁻), in the order of the epoch's available channels.
    pub innovations: Vec<f64>,
    /// Fusion weights ω_i (CI filters) or model probabilities (banks).
    pub weights: Option<Vec<f64>>,
    /// Per scalar measurement: the channel slot and its normalised innovation squared ν²/s
    /// (sequential EKF updates: the conditional ν_i²/s_i, independent χ²(1) terms for a
    /// consistent filter; batch updates: the marginal ν_i²/S_ii). What a flight team can check
    /// without the truth.
    pub nis_terms: Vec<(usize, f64)>,
    /// What the innovation gate did (None when the filter runs without `[filter.gating]`).
    pub gate: Option<GateReport>,
}
