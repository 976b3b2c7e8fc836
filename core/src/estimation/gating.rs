//! Innovation gating and beacon fault detection and exclusion (FDE).
//!
//! **Gate.** At a measurement epoch with prior x̂⁻, P⁻ and the linearised channels
//! `(h(x̂⁻), H, z, r)`, the innovations ν = z − h(x̂⁻) have the predicted covariance
//! S = H P⁻ Hᵀ + R. A consistent filter's ν is N(0, S), so ν_c²/S_cc ~ χ²₁ per channel and
//! νᵀS⁻¹ν ~ χ²_m jointly (the validation gate of Bar-Shalom, Li & Kirubarajan, *Estimation with
//! Applications to Tracking and Navigation*, Wiley 2001; the residual editing of flight
//! navigation filters). The gate rejects every channel with ν_c²/S_cc > χ²₁⁻¹(p); then, while
//! the survivors' joint νᵀS⁻¹ν exceeds χ²_m⁻¹(p), it rejects the survivor with the largest ν_c²/S_cc
//! (one bad channel hidden among good ones fails the joint test even when it passes its own).
//! With probability p a consistent filter loses 1 − p of its measurements to the gate.
//!
//! **Exclusion.** A beacon with a rejected channel at `exclude_after` consecutive epochs where it
//! was heard is excluded: its channels no longer reach the update. An excluded beacon is still
//! tested at every epoch against the gate; after `readmit_after` consecutive epochs with every
//! channel inside the gate it is re-admitted. Seed 000 (§4.2) argues its distributed fusion is
//! reliable when a beacon fails; gating and exclusion are what makes a wrong measurement (not
//! only a missing one) survivable.

use super::chi_square::chi_square_quantile;
use nalgebra::{DMatrix, DVector};
use serde::{Deserialize, Serialize};

/// `[filter.gating]`: innovation gating and beacon exclusion of every filter (absent: no gating).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct GatingConfig {
    /// Whether the gate is on (`--set filter.gating.enabled=false` runs the same scenario
    /// without it, for comparison).
    #[serde(default = "yes")]
    pub enabled: bool,
    /// Gate probability p in [0.9, 1): a channel is rejected when its normalised innovation
    /// squared exceeds the χ²₁ p-quantile, a set of m channels when it exceeds the χ²_m one.
    #[serde(default = "default_probability")]
    pub probability: f64,
    /// Also test the surviving channels jointly (νᵀS⁻¹ν against χ²_m).
    #[serde(default = "yes")]
    pub joint: bool,
    /// Exclude a beacon after this many consecutive epochs with a rejected channel (1..=1000).
    #[serde(default = "default_exclude_after")]
    pub exclude_after: usize,
    /// Re-admit an excluded beacon after this many consecutive epochs inside the gate (1..=100000).
    #[serde(default = "default_readmit_after")]
    pub readmit_after: usize,
}

fn default_probability() -> f64 {
    0.9999
}
fn yes() -> bool {
    true
}
fn default_exclude_after() -> usize {
    3
}
fn default_readmit_after() -> usize {
    10
}

impl Default for GatingConfig {
    fn default() -> Self {
        GatingConfig {
            enabled: true,
            probability: default_probability(),
            joint: true,
            exclude_after: default_exclude_after(),
            readmit_after: default_readmit_after(),
        }
    }
}

/// The gate's thresholds χ²ₖ⁻¹(p) for k = 1…`max_dof`, computed once.
#[derive(Debug, Clone, PartialEq)]
pub struct Gate {
    config: GatingConfig,
    /// `thresholds[k − 1]` = χ²ₖ⁻¹(p).
    thresholds: Vec<f64>,
}

impl Gate {
    /// A gate for epochs of at most `max_dof` scalar channels.
    pub fn new(config: GatingConfig, max_dof: usize) -> Self {
        let thresholds = (1..=max_dof.max(1))
            .map(|k| chi_square_quantile(config.probability, k))
            .collect();
        Gate { config, thresholds }
    }

    /// The settings.
    pub fn config(&self) -> &GatingConfig {
        &self.config
    }

    /// The threshold for `dof` channels (the largest computed one beyond `max_dof`, which a
    /// caller never passes: it is the number of channels).
    pub fn threshold(&self, dof: usize) -> f64 {
        let i = dof.clamp(1, self.thresholds.len()) - 1;
        self.thresholds[i]
    }

    /// Which channels pass: `nu` the innovations, `s` their predicted covariance H P⁻ Hᵀ + R.
    /// Returns per channel whether it is accepted and its ν_c²/S_cc. A channel whose S_cc is not
    /// positive is rejected (nothing can be learnt from it safely).
    pub fn decide(&self, nu: &DVector<f64>, s: &DMatrix<f64>) -> (Vec<bool>, Vec<f64>) {
        let m = nu.len();
        let terms: Vec<f64> = (0..m)
            .map(|c| {
                let scc = s[(c, c)];
                if scc > 0.0 && scc.is_finite() {
                    nu[c] * nu[c] / scc
                } else {
                    f64::INFINITY
                }
            })
            .collect();
        let mut accepted: Vec<bool> = terms.iter().map(|t| *t <= self.threshold(1)).collect();
        if !self.config.joint {
            return (accepted, terms);
        }
        loop {
            let idx: Vec<usize> = (0..m).filter(|&c| accepted[c]).collect();
            if idx.len() < 2 {
                break;
            }
            let sub_s = DMatrix::from_fn(idx.len(), idx.len(), |i, j| s[(idx[i], idx[j])]);
            let sub_nu = DVector::from_fn(idx.len(), |i, _| nu[idx[i]]);
            let joint = match sub_s.cholesky() {
                Some(ch) => sub_nu.dot(&ch.solve(&sub_nu)),
                None => f64::INFINITY,
            };
            if joint <= self.threshold(idx.len()) {
                break;
            }
            let worst = idx
                .iter()
                .copied()
                .max_by(|&a, &b| terms[a].total_cmp(&terms[b]))
                .unwrap_or(idx[0]);
            accepted[worst] = false;
        }
        (accepted, terms)
    }
}

/// A change of a beacon's exclusion.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ExclusionEvent {
    /// Epoch time \[s\].
    pub t: f64,
    /// Beacon index.
    pub beacon: usize,
    /// True: excluded at `t`; false: re-admitted at `t`.
    pub excluded: bool,
}

/// Per-beacon fault detection and exclusion state.
#[derive(Debug, Clone, PartialEq)]
pub struct BeaconMonitor {
    exclude_after: usize,
    readmit_after: usize,
    /// Consecutive heard epochs with a rejected channel (included beacons) or with every channel
    /// inside the gate (excluded beacons).
    streak: Vec<usize>,
    excluded: Vec<bool>,
}

impl BeaconMonitor {
    /// A monitor of `n_beacons` beacons, all admitted.
    pub fn new(config: &GatingConfig, n_beacons: usize) -> Self {
        BeaconMonitor {
            exclude_after: config.exclude_after.max(1),
            readmit_after: config.readmit_after.max(1),
            streak: vec![0; n_beacons],
            excluded: vec![false; n_beacons],
        }
    }

    /// Whether beacon `b` is excluded.
    pub fn is_excluded(&self, b: usize) -> bool {
        self.excluded.get(b).copied().unwrap_or(false)
    }

    /// The excluded beacons.
    pub fn excluded(&self) -> Vec<usize> {
        (0..self.excluded.len())
            .filter(|&b| self.excluded[b])
            .collect()
    }

    /// Record one epoch: `heard[b]` = Some(true) when beacon b was heard and had a channel outside
    /// the gate, Some(false) when heard and inside, None when not heard (the streak holds).
    /// Returns the exclusion changes at this epoch.
    pub fn record(&mut self, t: f64, heard: &[Option<bool>]) -> Vec<ExclusionEvent> {
        let mut events = Vec::new();
        for (b, h) in heard.iter().enumerate().take(self.excluded.len()) {
            let Some(outside) = *h else { continue };
            let counts = if self.excluded[b] { !outside } else { outside };
            self.streak[b] = if counts { self.streak[b] + 1 } else { 0 };
            let limit = if self.excluded[b] {
                self.readmit_after
            } else {
                self.exclude_after
            };
            if self.streak[b] >= limit {
                self.excluded[b] = !self.excluded[b];
                self.streak[b] = 0;
                events.push(ExclusionEvent {
                    t,
                    beacon: b,
                    excluded: self.excluded[b],
                });
            }
        }
        events
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn per_channel_and_joint_gates() {
        let gate = Gate::new(GatingConfig::default(), 4);
        let s = DMatrix::<f64>::identity(3, 3);
        // All inside: 1, 1, 1 (joint 3 < χ²₃(0.9999) = 21.1).
        let (ok, _) = gate.decide(&DVector::from_vec(vec![1.0, -1.0, 1.0]), &s);
        assert_eq!(ok, vec![true, true, true]);
        // One wild value: rejected by its own gate (15.14 for one dof).
        let (ok, terms) = gate.decide(&DVector::from_vec(vec![1.0, 5.0, 1.0]), &s);
        assert_eq!(ok, vec![true, false, true]);
        assert!((terms[1] - 25.0).abs() < 1e-12);
        // Three values of 3.8σ each pass alone (14.4 < 15.14) but not together (43 > 21.1):
        // the joint gate drops the largest until the rest pass.
        let (ok, _) = gate.decide(&DVector::from_vec(vec![3.8, 3.7, 3.6]), &s);
        assert_eq!(ok.iter().filter(|a| **a).count(), 1);
        assert!(ok[2] && !ok[0] && !ok[1]);
        // Without the joint test all three pass.
        let per_channel = Gate::new(
            GatingConfig {
                joint: false,
                ..GatingConfig::default()
            },
            4,
        );
        let (ok, _) = per_channel.decide(&DVector::from_vec(vec![3.8, 3.7, 3.6]), &s);
        assert_eq!(ok, vec![true, true, true]);
    }

    #[test]
    fn monitor_excludes_after_a_streak_and_readmits() {
        let cfg = GatingConfig {
            exclude_after: 3,
            readmit_after: 2,
            ..GatingConfig::default()
        };
        let mut m = BeaconMonitor::new(&cfg, 2);
        // Beacon 0 outside twice, inside once: the streak restarts.
        for (t, o) in [(1.0, true), (2.0, true), (3.0, false)] {
            assert!(m.record(t, &[Some(o), Some(false)]).is_empty());
        }
        // Not heard: the streak holds; three outside in a row excludes.
        assert!(m.record(4.0, &[Some(true), None]).is_empty());
        assert!(m.record(5.0, &[None, None]).is_empty());
        assert!(m.record(6.0, &[Some(true), None]).is_empty());
        let ev = m.record(7.0, &[Some(true), Some(false)]);
        assert_eq!(
            ev,
            vec![ExclusionEvent {
                t: 7.0,
                beacon: 0,
                excluded: true
            }]
        );
        assert_eq!(m.excluded(), vec![0]);
        // Two epochs inside re-admit it.
        assert!(m.record(8.0, &[Some(false), None]).is_empty());
        let ev = m.record(9.0, &[Some(false), None]);
        assert!(ev.len() == 1 && !ev[0].excluded && !m.is_excluded(0));
    }
}
