//! What the innovation gate and the beacon monitor did over a Monte Carlo
//! ([`crate::estimation::gating`]): rejections per channel, the NIS before gating, and every
//! beacon exclusion judged against the truth's faults (`[[faults]]`, [`super::exclusions`]).

use super::run_record::RunRecord;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Gate sums over runs, folded in run order (serialisable for shards).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct GateSums {
    /// Runs that ran behind a gate.
    runs: u64,
    /// Per channel slot: samples the gate saw, rejected, withheld (beacon excluded).
    channels: Vec<[u64; 3]>,
    /// Sum and count of ν²/S before gating.
    nis_before: (f64, u64),
    /// Per beacon: runs with a false exclusion.
    false_runs: BTreeMap<String, u64>,
    /// Runs with a false exclusion of any beacon.
    false_any_runs: u64,
    /// Per beacon: detection delays \[s\] (first correct exclusion of each run), run order.
    delays: BTreeMap<String, Vec<f64>>,
}

impl GateSums {
    /// Fold one run in.
    pub(super) fn add(&mut self, rec: &RunRecord) {
        let mut gated = false;
        for e in &rec.epochs {
            let Some(g) = &e.gate else { continue };
            gated = true;
            for &(c, v) in &g.terms {
                self.slot(c)[0] += 1;
                self.nis_before.0 += v;
                self.nis_before.1 += 1;
            }
            for &c in &g.rejected {
                self.slot(c)[1] += 1;
            }
            for &c in &g.withheld {
                self.slot(c)[2] += 1;
            }
        }
        if !gated {
            return;
        }
        self.runs += 1;
        if rec.exclusions.iter().any(|x| x.after_fault_s.is_none()) {
            self.false_any_runs += 1;
        }
        let mut beacons: Vec<&String> = rec.exclusions.iter().map(|x| &x.beacon).collect();
        beacons.sort();
        beacons.dedup();
        for b in beacons {
            let mine = rec.exclusions.iter().filter(|x| &x.beacon == b);
            if mine.clone().any(|x| x.after_fault_s.is_none()) {
                *self.false_runs.entry(b.clone()).or_default() += 1;
            }
            if let Some(d) = mine.filter_map(|x| x.after_fault_s).reduce(f64::min) {
                self.delays.entry(b.clone()).or_default().push(d);
            }
        }
    }

    fn slot(&mut self, c: usize) -> &mut [u64; 3] {
        if self.channels.len() <= c {
            self.channels.resize(c + 1, [0; 3]);
        }
        &mut self.channels[c]
    }

    /// Add another block's sums (blocks merge in block order).
    pub(super) fn merge(&mut self, o: &GateSums) {
        self.runs += o.runs;
        for (c, v) in o.channels.iter().enumerate() {
            let s = self.slot(c);
            for k in 0..3 {
                s[k] += v[k];
            }
        }
        self.false_any_runs += o.false_any_runs;
        self.nis_before.0 += o.nis_before.0;
        self.nis_before.1 += o.nis_before.1;
        for (b, n) in &o.false_runs {
            *self.false_runs.entry(b.clone()).or_default() += n;
        }
        for (b, d) in &o.delays {
            self.delays
                .entry(b.clone())
                .or_default()
                .extend_from_slice(d);
        }
    }

    /// The summary, with channel and beacon names (None when no run was gated).
    pub(super) fn report(&self, channels: &[String]) -> Option<GatingSummary> {
        if self.runs == 0 {
            return None;
        }
        let name =
            |names: &[String], i: usize| names.get(i).cloned().unwrap_or_else(|| format!("#{i}"));
        let empty = Vec::new();
        let frac = |n: u64, d: u64| (d > 0).then(|| n as f64 / d as f64);
        let per_channel = self
            .channels
            .iter()
            .enumerate()
            .filter(|(_, v)| v[0] > 0)
            .map(|(c, v)| {
                (
                    name(channels, c),
                    ChannelGate {
                        samples: v[0],
                        rejected_frac: frac(v[1], v[0]).unwrap_or(0.0),
                        withheld_frac: frac(v[2], v[0]).unwrap_or(0.0),
                    },
                )
            })
            .collect();
        let mut names: Vec<&String> = self.false_runs.keys().chain(self.delays.keys()).collect();
        names.sort();
        names.dedup();
        let per_beacon = names
            .into_iter()
            .map(|b| {
                let d = self.delays.get(b).unwrap_or(&empty);
                let mut sorted = d.clone();
                sorted.sort_by(f64::total_cmp);
                (
                    b.clone(),
                    BeaconExclusions {
                        detected_runs: d.len() as u64,
                        false_exclusion_runs: self.false_runs.get(b).copied().unwrap_or(0),
                        detection_mean_s: (!d.is_empty())
                            .then(|| d.iter().sum::<f64>() / d.len() as f64),
                        detection_max_s: sorted.last().copied(),
                        detected_within_10s_frac: frac(
                            d.iter().filter(|x| **x <= 10.0).count() as u64,
                            self.runs,
                        ),
                    },
                )
            })
            .collect();
        let (seen, rejected) = self
            .channels
            .iter()
            .fold((0, 0), |(s, r), v| (s + v[0], r + v[1]));
        Some(GatingSummary {
            runs: self.runs,
            rejected_frac: frac(rejected, seen).unwrap_or(0.0),
            anis_before_gating_per_dof: (self.nis_before.1 > 0)
                .then(|| self.nis_before.0 / self.nis_before.1 as f64),
            false_exclusion_run_frac: frac(self.false_any_runs, self.runs).unwrap_or(0.0),
            per_channel,
            per_beacon,
        })
    }
}

/// One channel at the gate.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChannelGate {
    /// Samples the gate saw (available measurements).
    pub samples: u64,
    /// Fraction rejected by the χ² gate (≈ 1 − p for a consistent filter without faults).
    pub rejected_frac: f64,
    /// Fraction withheld because the beacon was excluded.
    pub withheld_frac: f64,
}

/// One beacon's exclusions over the runs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct BeaconExclusions {
    /// Runs in which a started bias fault on the beacon was detected (excluded).
    pub detected_runs: u64,
    /// Runs with an exclusion while no bias fault on the beacon had started.
    pub false_exclusion_runs: u64,
    /// Mean time from the fault's start to the exclusion \[s\].
    pub detection_mean_s: Option<f64>,
    /// Longest such time \[s\].
    pub detection_max_s: Option<f64>,
    /// Fraction of all gated runs in which the beacon was excluded within 10 s of its fault.
    pub detected_within_10s_frac: Option<f64>,
}

/// The gate's summary for one filter (`gating` in the trade summary).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct GatingSummary {
    /// Runs behind the gate.
    pub runs: u64,
    /// Fraction of all available measurements the χ² gate rejected.
    pub rejected_frac: f64,
    /// Mean ν²/S of every available measurement before gating (after gating: the consistency
    /// block's `anis_per_dof`).
    pub anis_before_gating_per_dof: Option<f64>,
    /// Fraction of runs with a false exclusion of any beacon.
    pub false_exclusion_run_frac: f64,
    /// Per channel.
    pub per_channel: BTreeMap<String, ChannelGate>,
    /// Per beacon that was ever excluded.
    pub per_beacon: BTreeMap<String, BeaconExclusions>,
}
