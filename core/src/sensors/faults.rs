//! Sensor faults of the truth (`[[faults]]`): what a wrong measurement looks like.
//!
//! A beacon outage (no measurement) is a beacon setting (`outages`, seed 000 §4.2). The faults
//! here make measurements *wrong* instead: a range bias that steps in at a time and may drift (a
//! beacon clock jump or a wrong ephemeris), range outliers (multipath), an accelerometer bias
//! jump and accelerometer spikes. They act on the truth's sensors only; the onboard models never
//! see them, which is the point of innovation gating ([`crate::estimation::gating`]).
//!
//! Random faults (outliers, spikes) draw from the run's measurement random stream, after the
//! channel's noise, at *every* due epoch of an affected channel whether or not the fault has
//! started or the sample is available; a scenario without random faults draws exactly what it
//! drew before faults existed.

use super::channels::Channel;
use rand::Rng;
use rand_distr::{Distribution, StandardUniform};
use serde::{Deserialize, Serialize};

/// One fault, as written in the scenario (`[[faults]]`, `kind = "…"`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "kind", rename_all = "kebab-case", deny_unknown_fields)]
pub enum FaultConfig {
    /// From `start_s` the range to `beacon` reads `bias_m + drift_mps·(t − start_s)` too long.
    RangeBias {
        /// Beacon name.
        beacon: String,
        /// Start time \[s\].
        start_s: f64,
        /// Bias step \[m\].
        #[serde(default)]
        bias_m: f64,
        /// Bias drift \[m/s\].
        #[serde(default)]
        drift_mps: f64,
    },
    /// From `start_s` the range to `beacon` is stuck: every sample repeats the first one taken
    /// at or after `start_s` (a frozen transponder reading).
    RangeStuck {
        /// Beacon name.
        beacon: String,
        /// Start time \[s\].
        start_s: f64,
    },
    /// From `start_s` each range sample of `beacon` (every beacon when absent) is, with
    /// `probability`, off by ±`size_m` (sign drawn with equal odds).
    RangeOutliers {
        /// Beacon name; absent: every beacon.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        beacon: Option<String>,
        /// Start time \[s\].
        #[serde(default)]
        start_s: f64,
        /// Probability per sample in [0, 1].
        probability: f64,
        /// Outlier size \[m\].
        size_m: f64,
    },
    /// From `start_s` the accelerometer reads `bias_mps2` (per IMU axis) more.
    AccelBias {
        /// Start time \[s\].
        start_s: f64,
        /// Bias jump per IMU axis \[m/s²\].
        bias_mps2: [f64; 3],
    },
    /// From `start_s` each accelerometer sample is, with `probability`, off by ±`size_mps2`.
    AccelSpikes {
        /// Start time \[s\].
        #[serde(default)]
        start_s: f64,
        /// Probability per sample in [0, 1].
        probability: f64,
        /// Spike size \[m/s²\].
        size_mps2: f64,
    },
}

impl FaultConfig {
    /// The `kind` as written in the file.
    pub fn kind(&self) -> &'static str {
        match self {
            FaultConfig::RangeBias { .. } => "range-bias",
            FaultConfig::RangeStuck { .. } => "range-stuck",
            FaultConfig::RangeOutliers { .. } => "range-outliers",
            FaultConfig::AccelBias { .. } => "accel-bias",
            FaultConfig::AccelSpikes { .. } => "accel-spikes",
        }
    }

    /// The beacon name the fault refers to, if any.
    pub fn beacon(&self) -> Option<&str> {
        match self {
            FaultConfig::RangeBias { beacon, .. } | FaultConfig::RangeStuck { beacon, .. } => {
                Some(beacon)
            }
            FaultConfig::RangeOutliers { beacon, .. } => beacon.as_deref(),
            _ => None,
        }
    }
}

/// Which channels a resolved fault acts on.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Target {
    /// The range channel of one beacon, or of every beacon (None).
    Range(Option<usize>),
    /// Every accelerometer axis.
    Accel,
}

/// What a resolved fault adds.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Effect {
    /// `bias + drift·(t − start)` (per accelerometer axis for `Accel`: `axis_bias`).
    Bias { bias: f64, drift: f64 },
    /// Accelerometer bias per axis.
    AxisBias([f64; 3]),
    /// ±size with probability `p`.
    Random { p: f64, size: f64 },
    /// The sample repeats the first one taken at or after the start.
    Stuck,
}

/// A fault with its beacon resolved to an index.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Fault {
    target: Target,
    start_s: f64,
    effect: Effect,
}

impl Fault {
    /// Resolve `config` against the scenario's beacon names (None: an unknown beacon name, which
    /// validation reports first).
    pub fn resolve(config: &FaultConfig, beacon_names: &[String]) -> Option<Fault> {
        let index = |name: &str| beacon_names.iter().position(|n| n == name);
        Some(match config {
            FaultConfig::RangeBias {
                beacon,
                start_s,
                bias_m,
                drift_mps,
            } => Fault {
                target: Target::Range(Some(index(beacon)?)),
                start_s: *start_s,
                effect: Effect::Bias {
                    bias: *bias_m,
                    drift: *drift_mps,
                },
            },
            FaultConfig::RangeStuck { beacon, start_s } => Fault {
                target: Target::Range(Some(index(beacon)?)),
                start_s: *start_s,
                effect: Effect::Stuck,
            },
            FaultConfig::RangeOutliers {
                beacon,
                start_s,
                probability,
                size_m,
            } => Fault {
                target: Target::Range(match beacon {
                    Some(b) => Some(index(b)?),
                    None => None,
                }),
                start_s: *start_s,
                effect: Effect::Random {
                    p: *probability,
                    size: *size_m,
                },
            },
            FaultConfig::AccelBias { start_s, bias_mps2 } => Fault {
                target: Target::Accel,
                start_s: *start_s,
                effect: Effect::AxisBias(*bias_mps2),
            },
            FaultConfig::AccelSpikes {
                start_s,
                probability,
                size_mps2,
            } => Fault {
                target: Target::Accel,
                start_s: *start_s,
                effect: Effect::Random {
                    p: *probability,
                    size: *size_mps2,
                },
            },
        })
    }

    /// The beacon whose range this fault makes persistently wrong (a bias, a drift or a stuck
    /// value, not random outliers): the beacon a correct exclusion removes, and from when.
    pub fn biased_beacon(&self) -> Option<(usize, f64)> {
        match (self.target, self.effect) {
            (Target::Range(Some(b)), Effect::Bias { bias, drift })
                if bias != 0.0 || drift != 0.0 =>
            {
                Some((b, self.start_s))
            }
            (Target::Range(Some(b)), Effect::Stuck) => Some((b, self.start_s)),
            _ => None,
        }
    }

    fn acts_on(&self, channel: Channel) -> Option<usize> {
        match (self.target, channel) {
            (Target::Range(None), Channel::Range(_)) => Some(0),
            (Target::Range(Some(b)), Channel::Range(i)) if b == i => Some(0),
            (Target::Accel, Channel::Accel(k)) => Some(k as usize),
            _ => None,
        }
    }
}

/// Whether a stuck fault holds `channel` at time `t`.
pub fn is_stuck(faults: &[Fault], channel: Channel, t: f64) -> bool {
    faults
        .iter()
        .any(|f| f.effect == Effect::Stuck && t >= f.start_s && f.acts_on(channel).is_some())
}

/// The error the `faults` add to a due sample of `channel` at time `t`, drawing the random
/// faults' values from `rng` (always, see the module documentation).
pub fn fault_error(faults: &[Fault], channel: Channel, t: f64, rng: &mut impl Rng) -> f64 {
    let mut error = 0.0;
    for f in faults {
        let Some(axis) = f.acts_on(channel) else {
            continue;
        };
        let started = t >= f.start_s;
        match f.effect {
            Effect::Bias { bias, drift } if started => error += bias + drift * (t - f.start_s),
            Effect::AxisBias(b) if started => error += b[axis.min(2)],
            Effect::Random { p, size } => {
                let u: f64 = StandardUniform.sample(rng);
                let v: f64 = StandardUniform.sample(rng);
                let sign = if v < 0.5 { 1.0 } else { -1.0 };
                if started && u < p {
                    error += sign * size;
                }
            }
            _ => {}
        }
    }
    error
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::sensors::Channel;
    use rand::SeedableRng;

    fn names() -> Vec<String> {
        vec!["a".into(), "b".into()]
    }

    #[test]
    fn bias_steps_in_and_drifts_on_its_beacon_only() {
        let f = Fault::resolve(
            &FaultConfig::RangeBias {
                beacon: "b".into(),
                start_s: 10.0,
                bias_m: 500.0,
                drift_mps: 2.0,
            },
            &names(),
        )
        .expect("beacon b exists");
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        assert_eq!(fault_error(&[f], Channel::Range(1), 9.0, &mut rng), 0.0);
        assert_eq!(fault_error(&[f], Channel::Range(1), 15.0, &mut rng), 510.0);
        assert_eq!(fault_error(&[f], Channel::Range(0), 15.0, &mut rng), 0.0);
        assert_eq!(
            fault_error(&[f], Channel::RangeRate(1), 15.0, &mut rng),
            0.0
        );
        assert_eq!(f.biased_beacon(), Some((1, 10.0)));
    }

    #[test]
    fn a_stuck_range_holds_from_its_start_on_its_beacon_only() {
        let f = Fault::resolve(
            &FaultConfig::RangeStuck {
                beacon: "a".into(),
                start_s: 5.0,
            },
            &names(),
        )
        .expect("beacon a exists");
        assert!(!is_stuck(&[f], Channel::Range(0), 4.9));
        assert!(is_stuck(&[f], Channel::Range(0), 5.0));
        assert!(!is_stuck(&[f], Channel::Range(1), 6.0));
        assert!(!is_stuck(&[f], Channel::RangeRate(0), 6.0));
        assert_eq!(f.biased_beacon(), Some((0, 5.0)));
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(1);
        assert_eq!(fault_error(&[f], Channel::Range(0), 6.0, &mut rng), 0.0);
    }

    #[test]
    fn outliers_have_their_rate_and_size() {
        let f = Fault::resolve(
            &FaultConfig::RangeOutliers {
                beacon: None,
                start_s: 0.0,
                probability: 0.01,
                size_m: 5000.0,
            },
            &names(),
        )
        .expect("no beacon to resolve");
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let n = 200_000;
        let errors: Vec<f64> = (0..n)
            .map(|i| fault_error(&[f], Channel::Range(i % 2), 1.0, &mut rng))
            .collect();
        let hits = errors.iter().filter(|e| **e != 0.0).count() as f64 / n as f64;
        // Binomial σ of the rate at n = 2e5: 2.2e-4; allow 5σ.
        assert!((hits - 0.01).abs() < 1.2e-3, "outlier rate {hits}");
        assert!(errors.iter().all(|e| *e == 0.0 || e.abs() == 5000.0));
        assert!(errors.iter().any(|e| *e > 0.0) && errors.iter().any(|e| *e < 0.0));
        assert!(
            Fault::resolve(
                &FaultConfig::RangeBias {
                    beacon: "zz".into(),
                    start_s: 0.0,
                    bias_m: 1.0,
                    drift_mps: 0.0
                },
                &names()
            )
            .is_none()
        );
    }
}
