//! δ(t) along a scenario's trajectory, for the centralised system and for the distributed
//! subsystems of seed 000 §2.3.3 (IMU + one beacon, eq. 9; Fig. 2–3).

use super::degree::{Degree, Scaling, degree};
use super::error::ObservabilityError;
use super::method::{Method, observability_matrix};
use super::system::{AnalysisPoint, ObservedSystem, ScenarioSystem};
use crate::scenario::Scenario;
use crate::sensors::Noise;
use crate::state_dim::{DimVisitor, with_state_dim};
use nalgebra::SVector;

/// A named subset of a scenario's channels.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct ChannelSet {
    /// Name used in reports (`centralised`, `imu+surface-1`, …).
    pub name: String,
    /// Indices into `Scenario::channels`.
    pub channels: Vec<usize>,
}

impl ChannelSet {
    /// Every channel of the scenario (the centralised system, seed 000 eq. 8).
    pub fn centralised(scenario: &Scenario) -> ChannelSet {
        ChannelSet {
            name: "centralised".into(),
            channels: (0..scenario.channels.len()).collect(),
        }
    }

    /// One subsystem per beacon with radio channels: every non-radio channel (the IMU, and air
    /// data if any — the common reference sensors) plus that beacon's range and range-rate
    /// (seed 000 eq. 9). Empty when the scenario has no beacon channels.
    pub fn subsystems(scenario: &Scenario) -> Vec<ChannelSet> {
        let common: Vec<usize> = (0..scenario.channels.len())
            .filter(|&c| scenario.channels[c].channel.beacon().is_none())
            .collect();
        let prefix = if common.is_empty() { "" } else { "imu+" };
        (0..scenario.beacons.len())
            .filter_map(|b| {
                let own: Vec<usize> = (0..scenario.channels.len())
                    .filter(|&c| scenario.channels[c].channel.beacon() == Some(b))
                    .collect();
                if own.is_empty() {
                    return None;
                }
                let mut channels = common.clone();
                channels.extend(own);
                let name = scenario.beacon_names.get(b).cloned().unwrap_or_default();
                Some(ChannelSet {
                    name: format!("{prefix}{name}"),
                    channels,
                })
            })
            .collect()
    }
}

/// δ at one analysis point.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DegreeSample {
    /// Time \[s\].
    pub t: f64,
    /// δ of O in raw SI units.
    pub raw: Degree,
    /// δ of the scaled O (see [`Scaling`]).
    pub scaled: Degree,
    /// Number of scalar channels available at `t` (rows per Lie order).
    pub outputs: usize,
}

/// δ(t) of one channel set.
#[derive(Debug, Clone, PartialEq)]
pub struct DegreeSeries {
    /// The channel set's name.
    pub name: String,
    /// Method used.
    pub method: Method,
    /// One sample per analysis point.
    pub samples: Vec<DegreeSample>,
}

/// Minimum, maximum and time of the minimum of a δ series.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DeltaSummary {
    /// Smallest δ.
    pub min: f64,
    /// Largest δ.
    pub max: f64,
    /// Time of the (first) smallest δ \[s\].
    pub t_min_s: f64,
    /// Time of the (first) largest δ \[s\].
    pub t_max_s: f64,
}

impl DegreeSeries {
    /// Times \[s\].
    pub fn times(&self) -> Vec<f64> {
        self.samples.iter().map(|s| s.t).collect()
    }

    /// Raw-SI δ values (`scaled = false`) or scaled δ values (`true`).
    pub fn deltas(&self, scaled: bool) -> Vec<f64> {
        self.samples
            .iter()
            .map(|s| if scaled { s.scaled.delta } else { s.raw.delta })
            .collect()
    }

    /// Summary of the raw (`scaled = false`) or scaled δ; `None` for an empty series.
    pub fn summary(&self, scaled: bool) -> Option<DeltaSummary> {
        let d = self.deltas(scaled);
        let first = *d.first()?;
        let mut s = DeltaSummary {
            min: first,
            max: first,
            t_min_s: self.samples[0].t,
            t_max_s: self.samples[0].t,
        };
        for (v, p) in d.iter().zip(&self.samples) {
            if *v < s.min {
                (s.min, s.t_min_s) = (*v, p.t);
            }
            if *v > s.max {
                (s.max, s.t_max_s) = (*v, p.t);
            }
        }
        Some(s)
    }
}

/// δ(t) of the channel set `set` at every analysis point, with `method`, in raw SI units and
/// scaled by `scaling`. Radio channels whose beacon is unavailable at a point are left out there.
pub fn degree_series(
    scenario: &Scenario,
    points: &[AnalysisPoint],
    set: &ChannelSet,
    method: Method,
    scaling: &Scaling,
) -> Result<DegreeSeries, ObservabilityError> {
    let n = scenario.filter_model().state_dim();
    let visitor = Series {
        scenario,
        points,
        set,
        method,
        scaling,
    };
    let samples = with_state_dim(n, visitor)
        .map_err(|_| ObservabilityError::UnsupportedDimension { n })??;
    Ok(DegreeSeries {
        name: set.name.clone(),
        method,
        samples,
    })
}

struct Series<'a> {
    scenario: &'a Scenario,
    points: &'a [AnalysisPoint],
    set: &'a ChannelSet,
    method: Method,
    scaling: &'a Scaling,
}

impl DimVisitor for Series<'_> {
    type Output = Result<Vec<DegreeSample>, ObservabilityError>;

    fn visit<const N: usize, const L: usize>(self) -> Self::Output {
        series_n::<N>(
            self.scenario,
            self.points,
            self.set,
            self.method,
            self.scaling,
        )
    }
}

fn series_n<const N: usize>(
    scenario: &Scenario,
    points: &[AnalysisPoint],
    set: &ChannelSet,
    method: Method,
    scaling: &Scaling,
) -> Result<Vec<DegreeSample>, ObservabilityError> {
    let mut out = Vec::with_capacity(points.len());
    for p in points {
        if p.state.len() != N {
            return Err(ObservabilityError::InvalidInput(format!(
                "analysis point at t = {} s has {} states, the filter model {N}",
                p.t,
                p.state.len()
            )));
        }
        let x0 = SVector::<f64, N>::from_column_slice(&p.state);
        let mut specs = Vec::with_capacity(set.channels.len());
        for &c in &set.channels {
            let spec = scenario.channels.get(c).ok_or_else(|| {
                ObservabilityError::InvalidInput(format!("channel index {c} out of range"))
            })?;
            let available = spec
                .channel
                .beacon()
                .is_none_or(|b| p.available.get(b).copied().unwrap_or(false));
            if available {
                specs.push(spec);
            }
        }
        let sys = ScenarioSystem {
            model: scenario.filter_model(),
            measurement: &scenario.measurement,
            channels: specs.iter().map(|s| s.channel).collect(),
            beacons: p.beacons.clone(),
            t: p.t,
            bank: scenario.truth_bank,
        };
        let mut y = vec![0.0; specs.len()];
        ObservedSystem::<N>::h(&sys, &x0, &mut y);
        let mut sigma = Vec::with_capacity(specs.len());
        for (spec, v) in specs.iter().zip(&y) {
            let s = match spec.noise {
                Noise::Absolute(s) => s,
                Noise::Relative(f) => f * v.abs(),
            };
            if !(s.is_finite() && s > 0.0) {
                return Err(ObservabilityError::BadNoise {
                    channel: spec.name.clone(),
                    sigma: s,
                    t_s: p.t,
                });
            }
            sigma.push(s);
        }
        let o = observability_matrix(&sys, &x0, method);
        let raw = degree(&o).map_err(|e| e.at(p.t))?;
        let scaled = degree(&scaling.apply(&o, &sigma)?).map_err(|e| e.at(p.t))?;
        out.push(DegreeSample {
            t: p.t,
            raw,
            scaled,
            outputs: specs.len(),
        });
    }
    Ok(out)
}
