//! Tuning the entry navigation filters of a scenario: which factors are tuned, and how a set of
//! factors becomes a re-tuned onboard view evaluated over recorded Monte Carlo runs.
//!
//! Factors act on groups of the scenario's process-noise diagonal that describe one physical
//! quantity (spherical: r; lon and lat; v; flight-path angle and heading; Cartesian: position;
//! velocity; then each augmented state), so the search stays small and the tuned Q keeps the
//! scenario's proportions inside a group. An entry whose base value is zero cannot be scaled
//! and is not tuned (consider parameters never are). With measurement-noise tuning, one factor
//! per channel kind multiplies the 1σ the filter assumes (`filter.noise_inflation`). A filter
//! with the load-scaled process-noise model (`[filter.process_noise]`, `model = "aero-scaled"`)
//! has its fractions tuned too: the drag axis and the side/lift axes, one factor each.
//!
//! One filter is tuned at a time, from the tuning it flies with now (its own
//! `[filter.tuned.<name>]` if the scenario has one, else the shared `[filter]` values), and the
//! result is written as that filter's own tuning: tuning the UKF never changes the EKF.

use crate::error::{StudyError, StudyResult};
pub use crate::tune::groups::ParameterGroup;
use crate::tune::search::{Measured, THETA_BOUND, TuningProblem};
use crate::tune::verdict::{rmse_avg, rmse_final};
use entrynav::estimation::MAX_DENSITY_SIGMA;
use entrynav::estimation::Onboard;
use entrynav::estimation::ProcessNoiseModel;
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::config::{MAX_AERO_FRACTION, MAX_NOISE_INFLATION};
use entrynav::scenario::{FilterRetuneConfig, ScenarioConfig};
use entrynav::sensors::Channel;
use entrynav::sim::monte_carlo::report::FilterReport;
use entrynav::sim::monte_carlo::tuning::TuningRuns;
use std::sync::Arc;

/// The entry filter `kind` of the scenario of `runs`, tuned by group factors.
pub struct EntryTuning<'a> {
    runs: &'a TuningRuns,
    kind: FilterKind,
    /// The onboard view the filter flies with before tuning (its own tuning applied).
    base: Arc<Onboard>,
    groups: Vec<ParameterGroup>,
    /// Per group, the range of θ: a noise factor times the filter's current one stays within
    /// what a scenario accepts (at most [`MAX_NOISE_INFLATION`]), so the tuning can be written.
    bounds: Vec<(f64, f64)>,
}

fn same_kind(a: Channel, b: Channel) -> bool {
    std::mem::discriminant(&a) == std::mem::discriminant(&b)
}

impl<'a> EntryTuning<'a> {
    /// Tune `kind` over `runs`; with `tune_noise`, the assumed measurement noise too.
    pub fn new(runs: &'a TuningRuns, kind: FilterKind, tune_noise: bool) -> StudyResult<Self> {
        let sc = runs.scenario();
        let base = sc.onboard.for_filter(kind);
        let onboard = &base;
        let names = entrynav::sim::state_names(sc);
        let q = &onboard.tuning.q_diag;
        let n_est = onboard.state_dim() - onboard.tuning.n_consider;
        let kinematic: Vec<Vec<usize>> = if sc.filter_model().kind.is_cartesian() {
            vec![vec![0, 1, 2], vec![3, 4, 5]]
        } else {
            vec![vec![0], vec![1, 2], vec![3], vec![4, 5]]
        };
        let mut groups = Vec::new();
        for states in kinematic.into_iter().chain((6..n_est).map(|i| vec![i])) {
            let states: Vec<usize> = states
                .into_iter()
                .filter(|&i| q.get(i).is_some_and(|v| *v > 0.0))
                .collect();
            if states.is_empty() {
                continue;
            }
            let label: Vec<&str> = states.iter().map(|&i| names[i].as_str()).collect();
            groups.push(ParameterGroup::Process {
                name: format!("q[{}]", label.join(",")),
                states,
            });
        }
        if let ProcessNoiseModel::AeroScaled(a) = onboard.tuning.process_noise {
            for (name, axes) in [("aero[drag]", vec![0]), ("aero[side,lift]", vec![1, 2])] {
                let axes: Vec<usize> = axes.into_iter().filter(|&k| a.fraction[k] > 0.0).collect();
                if !axes.is_empty() {
                    groups.push(ParameterGroup::Aero {
                        name: name.to_string(),
                        axes,
                    });
                }
            }
            if a.density_sigma > 0.0 {
                groups.push(ParameterGroup::Density);
            }
        }
        if tune_noise {
            let mut kinds_seen: Vec<Channel> = Vec::new();
            for ch in &onboard.channels {
                if !kinds_seen.iter().any(|k| same_kind(*k, ch.channel)) {
                    kinds_seen.push(ch.channel);
                    let label = match ch.channel {
                        Channel::Accel(_) => "accel",
                        Channel::DynamicPressure => "dynamic_pressure",
                        Channel::Heating => "heating",
                        Channel::Range(_) => "range",
                        Channel::RangeRate(_) => "range_rate",
                    };
                    groups.push(ParameterGroup::Noise {
                        name: format!("r[{label}]"),
                        kind: ch.channel,
                    });
                }
            }
        }
        let current = sc
            .config
            .filter
            .tuned
            .get(kind.name())
            .and_then(|c| c.noise_inflation)
            .or(sc.config.filter.noise_inflation)
            .unwrap_or_default();
        let bounds = groups
            .iter()
            .map(|g| g.bounds(&onboard.tuning.process_noise, &current))
            .collect();
        Ok(EntryTuning {
            runs,
            kind,
            base,
            groups,
            bounds,
        })
    }

    /// The filter tuned.
    pub fn kind(&self) -> FilterKind {
        self.kind
    }

    /// The tuned factors, in θ order.
    pub fn groups(&self) -> &[ParameterGroup] {
        &self.groups
    }

    /// The process-noise diagonal, process-noise model and per-channel noise factors of θ.
    fn tuning(&self, theta: &[f64]) -> (Vec<f64>, ProcessNoiseModel, Vec<f64>) {
        let onboard = &self.base;
        let mut q = onboard.tuning.q_diag.clone();
        let mut model = onboard.tuning.process_noise;
        let mut noise = vec![1.0; onboard.channels.len()];
        for (g, t) in self.groups.iter().zip(theta) {
            let f = 10f64.powf(*t);
            match g {
                ParameterGroup::Process { states, .. } => {
                    for &i in states {
                        q[i] *= f;
                    }
                }
                ParameterGroup::Aero { axes, .. } => {
                    if let ProcessNoiseModel::AeroScaled(a) = &mut model {
                        for &k in axes {
                            a.fraction[k] = (a.fraction[k] * f).min(MAX_AERO_FRACTION);
                        }
                    }
                }
                ParameterGroup::Density => {
                    if let ProcessNoiseModel::AeroScaled(a) = &mut model {
                        a.density_sigma = (a.density_sigma * f).min(MAX_DENSITY_SIGMA);
                    }
                }
                ParameterGroup::Noise { kind, .. } => {
                    for (c, ch) in onboard.channels.iter().enumerate() {
                        if same_kind(ch.channel, *kind) {
                            noise[c] = f;
                        }
                    }
                }
            }
        }
        (q, model, noise)
    }

    /// The report of the filter tuned by θ over `runs` (the tuning runs or fresh ones of the
    /// same scenario).
    pub fn report(&self, theta: &[f64], runs: &TuningRuns) -> StudyResult<FilterReport> {
        let (q, model, noise) = self.tuning(theta);
        let mut onboard = self.base.with_tuning(&q, &noise);
        onboard.tuning.process_noise = model;
        let onboard = Arc::new(onboard);
        let mut reports = runs.evaluate(&onboard, &[self.kind])?;
        reports.pop().ok_or_else(|| {
            StudyError::Refused(format!(
                "invalid input: no report for filter {}",
                self.kind.name()
            ))
        })
    }

    /// The filter's own tuning under θ, as written to `[filter.tuned.<name>]` of the scenario
    /// configuration `base` (the one the runs were built from): the full Q diagonal, and with
    /// measurement-noise tuning the noise factors (the filter's current ones times the tuned
    /// factors).
    pub fn retune_config(&self, base: &ScenarioConfig, theta: &[f64]) -> FilterRetuneConfig {
        let (q, model, _) = self.tuning(theta);
        let current = base.filter.tuned.get(self.kind.name());
        let mut inflation = current
            .and_then(|c| c.noise_inflation)
            .or(base.filter.noise_inflation)
            .unwrap_or_default();
        let mut changed = false;
        for (g, t) in self.groups.iter().zip(theta) {
            if let ParameterGroup::Noise { kind, .. } = g {
                // Within the scenario's range by the search bounds (the min only absorbs round-off).
                let f = inflation.factor(*kind) * 10f64.powf(*t);
                inflation.set_factor(*kind, f.min(MAX_NOISE_INFLATION));
                changed = true;
            }
        }
        FilterRetuneConfig {
            q_diag: Some(q),
            process_noise: if model.is_constant() {
                current.and_then(|c| c.process_noise)
            } else {
                Some(model)
            },
            noise_inflation: if changed {
                Some(inflation)
            } else {
                current.and_then(|c| c.noise_inflation)
            },
        }
    }

    /// The scenario configuration `base` with the tuning θ written in as the filter's own
    /// `[filter.tuned.<name>]`.
    pub fn tuned_config(&self, base: &ScenarioConfig, theta: &[f64]) -> ScenarioConfig {
        let mut cfg = base.clone();
        cfg.filter.tuned.insert(
            self.kind.name().to_string(),
            self.retune_config(base, theta),
        );
        cfg
    }
}

/// The consistency of a set of reports: ANEES/dof and ANIS/dof averaged over the filters, the
/// fraction of failed or diverged runs over all filters.
pub fn measured(reports: &[FilterReport]) -> Measured {
    let mean = |v: Vec<f64>| (!v.is_empty()).then(|| v.iter().sum::<f64>() / v.len() as f64);
    let nees = mean(
        reports
            .iter()
            .filter_map(|r| {
                let c = &r.consistency;
                c.anees.map(|a| a / c.nees_dof.max(1) as f64)
            })
            .collect(),
    );
    let nis = mean(
        reports
            .iter()
            .filter_map(|r| r.consistency.anis_per_dof)
            .collect(),
    );
    let nees_in_band = mean(
        reports
            .iter()
            .filter_map(|r| r.consistency.nees_in_bounds_frac)
            .collect(),
    );
    let shapes: Vec<f64> = reports
        .iter()
        .filter_map(|r| {
            let dof = r.consistency.nees_dof.max(1) as f64;
            let terms: Vec<f64> = r
                .series
                .nees_mean
                .iter()
                .flatten()
                .map(|n| match n / dof {
                    v if v.is_finite() && v > 0.0 => v.ln().powi(2),
                    _ => 1e3,
                })
                .collect();
            mean(terms)
        })
        .collect();
    let nis_in_band = mean(
        reports
            .iter()
            .filter_map(|r| r.consistency.nis_in_bounds_frac)
            .collect(),
    );
    let channel_terms: Vec<f64> = reports
        .iter()
        .flat_map(|r| r.consistency.nis_per_channel.values())
        .map(|c| match c.anis_per_dof {
            v if v.is_finite() && v > 0.0 => v.ln().powi(2),
            _ => 1e3,
        })
        .collect();
    let runs: u64 = reports.iter().map(|r| r.runs).sum();
    let bad: u64 = reports.iter().map(|r| r.failed + r.diverged).sum();
    Measured {
        anees_per_dof: nees,
        anis_per_dof: nis,
        nees_in_band,
        nees_shape: mean(shapes),
        nis_in_band,
        channel_spread: mean(channel_terms).unwrap_or(0.0),
        pos_rmse: {
            let avg = mean(reports.iter().filter_map(rmse_avg).collect());
            let fin = mean(reports.iter().filter_map(rmse_final).collect());
            avg.zip(fin).map(|(a, f)| [a, f])
        },
        bad_fraction: if runs > 0 {
            bad as f64 / runs as f64
        } else {
            1.0
        },
    }
}

impl TuningProblem for EntryTuning<'_> {
    fn dim(&self) -> usize {
        self.groups.len()
    }

    fn bounds(&self, k: usize) -> (f64, f64) {
        self.bounds
            .get(k)
            .copied()
            .unwrap_or((-THETA_BOUND, THETA_BOUND))
    }

    fn evaluate(&self, theta: &[f64]) -> StudyResult<Measured> {
        Ok(measured(&[self.report(theta, self.runs)?]))
    }
}
