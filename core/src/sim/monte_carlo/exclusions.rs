//! Beacon exclusions judged against the truth's faults (`[[faults]]`): what one run's beacon
//! monitor did, right or wrong.
//!
//! An exclusion is **correct** when its beacon's range is biased by a fault that has started
//! (a range bias or drift, [`Fault::biased_beacon`](crate::sensors::Fault::biased_beacon)); every other exclusion is a **false
//! exclusion** (random outliers are transient: the gate, not exclusion, is what should handle
//! them). The detection time of a biased beacon is its first exclusion after the fault's start.

use crate::estimation::gating::ExclusionEvent;
use crate::scenario::Scenario;
use serde::{Deserialize, Serialize};

/// A beacon's exclusion in one run, judged against the truth.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct JudgedExclusion {
    /// Beacon name.
    pub beacon: String,
    /// Exclusion time \[s\].
    pub t_s: f64,
    /// Time since the bias fault on this beacon started \[s\] (None: no such fault had started,
    /// a false exclusion).
    pub after_fault_s: Option<f64>,
}

/// Judge a run's exclusion events against the scenario's faults.
pub fn judge_exclusions(scenario: &Scenario, events: &[ExclusionEvent]) -> Vec<JudgedExclusion> {
    events
        .iter()
        .filter(|e| e.excluded)
        .map(|e| {
            let after_fault_s = scenario
                .faults
                .iter()
                .filter_map(|f| f.biased_beacon())
                .filter(|(b, start)| *b == e.beacon && e.t >= *start)
                .map(|(_, start)| e.t - start)
                .reduce(f64::min);
            JudgedExclusion {
                beacon: scenario
                    .beacon_names
                    .get(e.beacon)
                    .cloned()
                    .unwrap_or_else(|| format!("#{}", e.beacon)),
                t_s: e.t,
                after_fault_s,
            }
        })
        .collect()
}
