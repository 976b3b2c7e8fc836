//! Filter consistency over a Monte Carlo: NEES over all states and over the six kinematic states,
//! NIS overall and per channel, with two-sided 95 % χ² bounds (Bar-Shalom, Li & Kirubarajan,
//! *Estimation with Applications to Tracking and Navigation*, §5.4).
//!
//! * **NEES** eᵀP⁻¹e needs the truth: per epoch the mean over runs, whose bounds for a consistent
//!   filter are χ²(runs·dof)/runs; ANEES is its time average. Reported over every state with a
//!   truth value (augmented parameters at their truth-equivalent values, see
//!   [`Scenario::truth_equivalent`](crate::scenario::Scenario::truth_equivalent)) and separately
//!   over the six kinematic states.
//! * **NIS** ν²/s needs no truth (what a flight team has): every scalar measurement's normalised
//!   innovation squared is χ²(1) for a consistent filter, independent across measurements and
//!   time. Per epoch the sum over runs of the NIS is χ²(Σ dof); ANIS is the time average of the
//!   per-epoch mean over runs, `anis_per_dof` the mean over every scalar term (≈ 1), and the
//!   per-channel means say which sensor the filter misjudges. Fusion filters contribute the
//!   terms of every local filter (the IMU channels once per local filter); banks the terms of
//!   their mixture's predictive distribution.

use super::run_record::EpochRecord;
use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;

/// Two-sided 95 % bounds for the mean of `runs` NEES values with `dof` degrees of freedom each
/// (χ² with runs·dof degrees, Wilson–Hilferty approximation, divided by `runs`).
pub fn nees_bounds_95(dof: usize, runs: usize) -> (f64, f64) {
    let k = (dof * runs).max(1) as f64;
    let q = |z: f64| k * (1.0 - 2.0 / (9.0 * k) + z * (2.0 / (9.0 * k)).sqrt()).powi(3);
    (
        q(-1.959_963_984_540_054).max(0.0) / runs.max(1) as f64,
        q(1.959_963_984_540_054) / runs.max(1) as f64,
    )
}

/// Consistency sums over runs, folded in run order (serialisable for shards).
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct ConsistencySums {
    nees_sum: Vec<f64>,
    nees_n: Vec<u64>,
    nees_dof: usize,
    kin_sum: Vec<f64>,
    kin_n: Vec<u64>,
    nis_sum: Vec<f64>,
    nis_dof: Vec<u64>,
    nis_runs: Vec<u64>,
    channel_sum: Vec<f64>,
    channel_n: Vec<u64>,
    /// Per channel slot, per epoch: the sum of the channel's ν²/s terms and their number.
    #[serde(default)]
    channel_epoch_sum: Vec<Vec<f64>>,
    #[serde(default)]
    channel_epoch_n: Vec<Vec<u64>>,
}

fn grow<T: Clone + Default>(v: &mut Vec<T>, n: usize) {
    if v.len() < n {
        v.resize(n, T::default());
    }
}

fn add<T: Copy + Default + std::ops::AddAssign>(a: &mut Vec<T>, b: &[T]) {
    grow(a, b.len());
    for (x, y) in a.iter_mut().zip(b) {
        *x += *y;
    }
}

impl ConsistencySums {
    /// Fold in epoch `k` of one run.
    pub(super) fn add_epoch(&mut self, k: usize, e: &EpochRecord) {
        for v in [&mut self.nees_sum, &mut self.kin_sum, &mut self.nis_sum] {
            grow(v, k + 1);
        }
        for v in [
            &mut self.nees_n,
            &mut self.kin_n,
            &mut self.nis_dof,
            &mut self.nis_runs,
        ] {
            grow(v, k + 1);
        }
        if let Some((nees, dof)) = e.nees {
            self.nees_sum[k] += nees;
            self.nees_n[k] += 1;
            self.nees_dof = dof;
        }
        if let Some(nees) = e.nees_kinematic {
            self.kin_sum[k] += nees;
            self.kin_n[k] += 1;
        }
        if !e.nis_terms.is_empty() {
            self.nis_runs[k] += 1;
        }
        for &(c, v) in &e.nis_terms {
            grow(&mut self.channel_sum, c + 1);
            grow(&mut self.channel_n, c + 1);
            self.nis_sum[k] += v;
            self.nis_dof[k] += 1;
            self.channel_sum[c] += v;
            self.channel_n[c] += 1;
            grow(&mut self.channel_epoch_sum, c + 1);
            grow(&mut self.channel_epoch_n, c + 1);
            grow(&mut self.channel_epoch_sum[c], k + 1);
            grow(&mut self.channel_epoch_n[c], k + 1);
            self.channel_epoch_sum[c][k] += v;
            self.channel_epoch_n[c][k] += 1;
        }
    }

    /// Add another block's sums (blocks merge in block order).
    pub(super) fn merge(&mut self, o: &ConsistencySums) {
        add(&mut self.nees_sum, &o.nees_sum);
        add(&mut self.nees_n, &o.nees_n);
        self.nees_dof = self.nees_dof.max(o.nees_dof);
        add(&mut self.kin_sum, &o.kin_sum);
        add(&mut self.kin_n, &o.kin_n);
        add(&mut self.nis_sum, &o.nis_sum);
        add(&mut self.nis_dof, &o.nis_dof);
        add(&mut self.nis_runs, &o.nis_runs);
        add(&mut self.channel_sum, &o.channel_sum);
        add(&mut self.channel_n, &o.channel_n);
        grow(&mut self.channel_epoch_sum, o.channel_epoch_sum.len());
        grow(&mut self.channel_epoch_n, o.channel_epoch_n.len());
        for (a, b) in self.channel_epoch_sum.iter_mut().zip(&o.channel_epoch_sum) {
            add(a, b);
        }
        for (a, b) in self.channel_epoch_n.iter_mut().zip(&o.channel_epoch_n) {
            add(a, b);
        }
    }

    /// Per channel slot, the per-epoch mean of its ν²/s terms over the runs (1 for a consistent
    /// filter).
    pub(super) fn channel_nis_series(&self) -> Vec<Vec<Option<f64>>> {
        self.channel_epoch_sum
            .iter()
            .zip(&self.channel_epoch_n)
            .map(|(s, n)| mean_series(s, n))
            .collect()
    }

    /// The fraction of channel `c`'s epochs whose mean term lies inside its 95 % band χ²(n)/n.
    fn channel_in_band(&self, c: usize) -> Option<f64> {
        let (sum, n) = (self.channel_epoch_sum.get(c)?, self.channel_epoch_n.get(c)?);
        let epochs: Vec<(f64, u64)> = sum
            .iter()
            .zip(n)
            .filter(|(_, n)| **n > 0)
            .map(|(s, n)| (*s, *n))
            .collect();
        (!epochs.is_empty()).then(|| {
            let inside = epochs
                .iter()
                .filter(|(s, n)| {
                    let (lo, hi) = nees_bounds_95(1, *n as usize);
                    (lo..=hi).contains(&(s / *n as f64))
                })
                .count();
            inside as f64 / epochs.len() as f64
        })
    }

    /// Per-epoch mean NEES over runs (all states with truth).
    pub(super) fn nees_series(&self) -> Vec<Option<f64>> {
        mean_series(&self.nees_sum, &self.nees_n)
    }

    /// Per-epoch mean NEES over runs (kinematic states).
    pub(super) fn nees_kinematic_series(&self) -> Vec<Option<f64>> {
        mean_series(&self.kin_sum, &self.kin_n)
    }

    /// Per-epoch mean NIS over the runs that measured something.
    pub(super) fn nis_series(&self) -> Vec<Option<f64>> {
        mean_series(&self.nis_sum, &self.nis_runs)
    }

    /// The summary, with channel names `channels` (epoch-slot order).
    pub(super) fn report(&self, channels: &[String]) -> Consistency {
        let (anees, nees_bounds, nees_in) = summarise(&self.nees_sum, &self.nees_n, self.nees_dof);
        let (anees_kin, kin_bounds, kin_in) = summarise(&self.kin_sum, &self.kin_n, 6);
        let nis = self.nis_series();
        let epochs: Vec<usize> = (0..nis.len()).filter(|&k| nis[k].is_some()).collect();
        let mean = |f: &dyn Fn(usize) -> f64| {
            (!epochs.is_empty())
                .then(|| epochs.iter().map(|&k| f(k)).sum::<f64>() / epochs.len() as f64)
        };
        let anis = mean(&|k| nis[k].unwrap_or(0.0));
        let nis_dof = mean(&|k| self.nis_dof[k] as f64 / self.nis_runs[k] as f64);
        let in_bounds = (!epochs.is_empty()).then(|| {
            epochs
                .iter()
                .filter(|&&k| {
                    let (lo, hi) = nees_bounds_95(self.nis_dof[k] as usize, 1);
                    (lo..=hi).contains(&self.nis_sum[k])
                })
                .count() as f64
                / epochs.len() as f64
        });
        let runs = self.nis_runs.iter().copied().max().unwrap_or(0) as usize;
        let nis_bounds = match nis_dof {
            Some(d) if runs > 0 => {
                let (lo, hi) = nees_bounds_95((d * runs as f64).round() as usize, 1);
                [lo / runs as f64, hi / runs as f64]
            }
            _ => [f64::NAN, f64::NAN],
        };
        let total_n: u64 = self.nis_dof.iter().sum();
        let anis_per_dof = (total_n > 0).then(|| self.nis_sum.iter().sum::<f64>() / total_n as f64);
        let nis_per_channel = self
            .channel_n
            .iter()
            .enumerate()
            .filter(|(_, n)| **n > 0)
            .map(|(c, &n)| {
                let name = channels
                    .get(c)
                    .cloned()
                    .unwrap_or_else(|| format!("channel{c}"));
                let (lo, hi) = nees_bounds_95(1, n as usize);
                (
                    name,
                    ChannelNis {
                        anis_per_dof: self.channel_sum[c] / n as f64,
                        samples: n,
                        bounds_95: [lo, hi],
                        epochs_in_band_frac: self.channel_in_band(c),
                    },
                )
            })
            .collect();
        Consistency {
            anees,
            nees_dof: self.nees_dof,
            nees_bounds_95: nees_bounds,
            nees_in_bounds_frac: nees_in,
            anees_kinematic: anees_kin,
            nees_kinematic_bounds_95: kin_bounds,
            nees_kinematic_in_bounds_frac: kin_in,
            anis,
            nis_dof,
            nis_bounds_95: nis_bounds,
            nis_in_bounds_frac: in_bounds,
            anis_per_dof,
            nis_per_channel,
        }
    }
}

fn mean_series(sum: &[f64], n: &[u64]) -> Vec<Option<f64>> {
    sum.iter()
        .zip(n)
        .map(|(s, &n)| (n > 0).then(|| s / n as f64))
        .collect()
}

/// Time average of the per-epoch mean, the 95 % bounds of a per-epoch mean for `dof` degrees of
/// freedom and the runs at the end, and the fraction of epochs inside.
fn summarise(sum: &[f64], n: &[u64], dof: usize) -> (Option<f64>, [f64; 2], Option<f64>) {
    let series: Vec<f64> = mean_series(sum, n).into_iter().flatten().collect();
    let runs = n.iter().copied().max().unwrap_or(0) as usize;
    let (lo, hi) = nees_bounds_95(dof, runs.max(1));
    if series.is_empty() {
        return (None, [lo, hi], None);
    }
    let avg = series.iter().sum::<f64>() / series.len() as f64;
    let inside = series.iter().filter(|v| (lo..=hi).contains(*v)).count() as f64;
    (Some(avg), [lo, hi], Some(inside / series.len() as f64))
}

/// NIS of one channel over all runs and epochs.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ChannelNis {
    /// Mean of the channel's ν²/s terms (1 for a consistent filter).
    pub anis_per_dof: f64,
    /// Number of terms.
    pub samples: u64,
    /// Two-sided 95 % bounds of that mean for a consistent filter, χ²(n)/n.
    pub bounds_95: [f64; 2],
    /// Fraction of the epochs at which the channel's mean term over the runs lies inside its
    /// 95 % band χ²(runs)/runs (≈ 0.95 for a consistent filter; `None`: never measured).
    pub epochs_in_band_frac: Option<f64>,
}

/// The consistency summary of one filter (part of its trade report).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct Consistency {
    /// Average NEES over epochs (of the per-epoch mean over runs), every state with a truth.
    pub anees: Option<f64>,
    /// Degrees of freedom of that NEES.
    pub nees_dof: usize,
    /// Two-sided 95 % bounds for the per-epoch mean NEES.
    pub nees_bounds_95: [f64; 2],
    /// Fraction of epochs whose mean NEES is inside the bounds.
    pub nees_in_bounds_frac: Option<f64>,
    /// ANEES over the six kinematic states (dof 6).
    pub anees_kinematic: Option<f64>,
    /// Two-sided 95 % bounds for the per-epoch mean kinematic NEES.
    pub nees_kinematic_bounds_95: [f64; 2],
    /// Fraction of epochs whose mean kinematic NEES is inside its bounds.
    pub nees_kinematic_in_bounds_frac: Option<f64>,
    /// Average NIS over epochs (of the per-epoch mean over runs).
    pub anis: Option<f64>,
    /// Mean number of scalar measurements per epoch (the NIS's degrees of freedom).
    pub nis_dof: Option<f64>,
    /// Two-sided 95 % bounds for a per-epoch mean NIS with `nis_dof` degrees of freedom.
    pub nis_bounds_95: [f64; 2],
    /// Fraction of epochs whose summed NIS is inside its χ²(Σ dof) bounds.
    pub nis_in_bounds_frac: Option<f64>,
    /// Mean of every scalar ν²/s term (1 for a consistent filter).
    pub anis_per_dof: Option<f64>,
    /// Per channel.
    pub nis_per_channel: BTreeMap<String, ChannelNis>,
}

#[cfg(test)]
mod tests {
    use super::*;

    fn epoch(terms: &[(usize, f64)]) -> EpochRecord {
        EpochRecord {
            err: vec![],
            sigma: vec![],
            pos_vel_err: (0.0, 0.0),
            local_err: [0.0; 3],
            nees: None,
            nees_kinematic: None,
            nis_terms: terms.to_vec(),
            density_rel_err: None,
            density_at_estimate_rel_err: None,
            weights: None,
            gate: None,
        }
    }

    /// Per channel and epoch: the mean term over the runs, the fraction of epochs inside the
    /// band χ²(runs)/runs, and shards that merge to the sums of one fold.
    #[test]
    fn channel_terms_over_time_and_their_band() {
        // Two runs, three epochs; channel 1 is measured only at epochs 0 and 2.
        let runs = [
            [
                vec![(0, 1.0), (1, 50.0)],
                vec![(0, 0.5)],
                vec![(0, 1.5), (1, 0.8)],
            ],
            [
                vec![(0, 1.0), (1, 30.0)],
                vec![(0, 1.5)],
                vec![(0, 0.5), (1, 1.2)],
            ],
        ];
        let mut one = ConsistencySums::default();
        let mut shards = [ConsistencySums::default(), ConsistencySums::default()];
        for (r, run) in runs.iter().enumerate() {
            for (k, terms) in run.iter().enumerate() {
                one.add_epoch(k, &epoch(terms));
                shards[r].add_epoch(k, &epoch(terms));
            }
        }
        let series = one.channel_nis_series();
        assert_eq!(series[0], vec![Some(1.0), Some(1.0), Some(1.0)]);
        assert_eq!(series[1], vec![Some(40.0), None, Some(1.0)]);
        let (lo, hi) = nees_bounds_95(1, 2);
        assert!(lo < 1.0 && 1.0 < hi && hi < 40.0, "{lo} {hi}");
        let report = one.report(&["a".into(), "b".into()]);
        assert_eq!(report.nis_per_channel["a"].epochs_in_band_frac, Some(1.0));
        assert_eq!(report.nis_per_channel["b"].epochs_in_band_frac, Some(0.5));
        let [mut merged, second] = shards;
        merged.merge(&second);
        assert_eq!(merged, one);
    }

    #[test]
    fn chi_square_bounds_match_tables() {
        // χ²(0.025, 100) = 74.22, χ²(0.975, 100) = 129.56 (standard tables).
        let (lo, hi) = nees_bounds_95(100, 1);
        assert!(
            (lo - 74.22).abs() < 0.1 && (hi - 129.56).abs() < 0.1,
            "{lo} {hi}"
        );
        // Mean of 50 runs of 8-dof NEES: χ²(0.025, 400) = 346.48, χ²(0.975, 400) = 457.31, over 50.
        let (lo, hi) = nees_bounds_95(8, 50);
        assert!(
            (lo - 346.48 / 50.0).abs() < 0.01 && (hi - 457.31 / 50.0).abs() < 0.01,
            "{lo} {hi}"
        );
    }
}
