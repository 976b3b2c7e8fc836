//! [`GateReport`]: what the innovation gate did at one update.

use crate::estimation::gating::ExclusionEvent;

/// What the gate did at one epoch.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct GateReport {
    /// Per available channel before gating: the slot and ν²/S at the prior.
    pub terms: Vec<(usize, f64)>,
    /// Channel slots the gate rejected (excluded beacons' channels not included).
    pub rejected: Vec<usize>,
    /// Channel slots withheld because their beacon is excluded.
    pub withheld: Vec<usize>,
    /// Beacons excluded after this epoch.
    pub excluded_beacons: Vec<usize>,
    /// Exclusions and re-admissions decided at this epoch.
    pub events: Vec<ExclusionEvent>,
    /// The gate opened for the radio channels: several admitted beacons have been outside it at
    /// once for `exclude_after` epochs (one fault at a time is assumed, so the prior is suspect).
    pub opened: bool,
}
