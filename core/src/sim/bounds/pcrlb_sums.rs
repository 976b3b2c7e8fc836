//! Run sums of the PCRLB inputs and the bound they give (see [`super::pcrlb`]).

use super::pcrlb::{BoundRun, bound_run};
use super::pcrlb_epochs::BoundRunData;
use crate::pcrlb_recursion::{BoundStep, pcrlb_recursion};
use crate::scenario::Scenario;
use crate::sim::engine::{RunError, record_run};
use crate::sim::monte_carlo::state_names::state_names;
use crate::sim::monte_carlo::trade_error::TradeError;
use nalgebra::DMatrix;
use rayon::prelude::*;
use serde::Serialize;
use std::collections::BTreeMap;

/// Sums over runs of F, I, JₚᵀJₚ and JᵥᵀJᵥ per epoch, folded in run order (serialisable so that
/// shards merge exactly).
#[derive(Debug, Clone, Default, PartialEq, Serialize, serde::Deserialize)]
pub struct BoundSums {
    pub(super) dim: usize,
    pub(super) p0_diag: Vec<f64>,
    pub(super) times: Vec<f64>,
    pub(super) count: Vec<u64>,
    pub(super) ends: Vec<u64>,
    pub(super) phi: Vec<Vec<f64>>,
    pub(super) info: Vec<Vec<f64>>,
    pub(super) pos: Vec<Vec<f64>>,
    pub(super) vel: Vec<Vec<f64>>,
    pub(super) unavailable: Option<String>,
    /// Whether the runs' filter start errors are drawn from P0 (`filter.sample_initial_from_p0`).
    #[serde(default)]
    pub(super) start_from_p0: bool,
}

/// The bound in a trade summary (`pcrlb`): per state and for `pos_m`/`vel_mps`, in the units of
/// the RMSE tables. `available` is false, with the reason, when the scenario has no bound.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct PcrlbReport {
    /// Whether the bound could be formed.
    pub available: bool,
    /// Why not, when it could not.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reason: Option<String>,
    /// The prior the bound assumes, and whether the runs' start errors follow it.
    pub prior: String,
    /// Time average over epochs of the bound's 1σ (compare `rmse_time_avg`).
    pub time_avg: BTreeMap<String, Option<f64>>,
    /// At each run's last epoch, root-mean-square over runs (compare `rmse_final`).
    #[serde(rename = "final")]
    pub final_: BTreeMap<String, Option<f64>>,
    /// Epoch times \[s\].
    pub times_s: Vec<f64>,
    /// The bound's 1σ per epoch, per state and for `pos_m`/`vel_mps`.
    pub series: BTreeMap<String, Vec<f64>>,
}

fn add_into(a: &mut Vec<f64>, b: &[f64]) {
    if a.len() < b.len() {
        a.resize(b.len(), 0.0);
    }
    for (x, y) in a.iter_mut().zip(b) {
        *x += y;
    }
}

impl BoundSums {
    /// Empty sums for `scenario` (its state size and filter start covariance, the prior).
    pub fn new(scenario: &Scenario) -> Self {
        let n = scenario.onboard.state_dim();
        let p0 = &scenario.onboard.tuning.p0_diag;
        BoundSums {
            dim: n,
            p0_diag: (0..n).map(|i| p0.get(i).copied().unwrap_or(1.0)).collect(),
            start_from_p0: scenario.config.filter.sample_initial_from_p0,
            ..Default::default()
        }
    }

    /// Fold consecutive runs in (call in run-index order). Every epoch's sums add the runs in
    /// run order, so the result is the same as folding them one by one; epochs are folded in
    /// parallel.
    pub fn add_runs<B: std::borrow::Borrow<BoundRun>>(&mut self, runs: &[B]) {
        let mut data: Vec<&BoundRunData> = Vec::with_capacity(runs.len());
        for run in runs {
            match run.borrow() {
                Ok(d) => data.push(d),
                Err(reason) => {
                    self.unavailable.get_or_insert_with(|| reason.to_string());
                }
            }
        }
        let n = self.dim;
        let Some(longest) = data
            .iter()
            .copied()
            .reduce(|a, b| if b.len() > a.len() { b } else { a })
        else {
            return;
        };
        let k = longest.len();
        if self.count.len() < k {
            self.count.resize(k, 0);
            self.ends.resize(k, 0);
            for v in [&mut self.phi, &mut self.info, &mut self.pos, &mut self.vel] {
                v.resize(k, vec![0.0; n * n]);
            }
        }
        if self.times.len() < k {
            self.times = longest.times.clone();
        }
        (
            &mut self.count[..k],
            &mut self.phi[..k],
            &mut self.info[..k],
            &mut self.pos[..k],
            &mut self.vel[..k],
        )
            .into_par_iter()
            .with_min_len(16)
            .enumerate()
            .for_each(|(i, (count, phi, info, pos, vel))| {
                for run in data.iter().filter(|r| i < r.len() && r.dim() == n) {
                    *count += 1;
                    run.add_epoch_into(i, phi, info, pos, vel);
                }
            });
        for run in data.iter().filter(|r| !r.is_empty() && r.dim() == n) {
            self.ends[run.len() - 1] += 1;
        }
    }

    /// Add another block's sums (in block order).
    pub fn merge(&mut self, o: &BoundSums) {
        if self.dim == 0 {
            self.dim = o.dim;
            self.p0_diag = o.p0_diag.clone();
            self.start_from_p0 = o.start_from_p0;
        }
        if self.unavailable.is_none() {
            self.unavailable = o.unavailable.clone();
        }
        if self.times.len() < o.times.len() {
            self.times = o.times.clone();
        }
        let k = o.count.len();
        if self.count.len() < k {
            self.count.resize(k, 0);
            self.ends.resize(k, 0);
            let n2 = self.dim * self.dim;
            for v in [&mut self.phi, &mut self.info, &mut self.pos, &mut self.vel] {
                v.resize(k, vec![0.0; n2]);
            }
        }
        for i in 0..k {
            self.count[i] += o.count[i];
            self.ends[i] += o.ends[i];
            add_into(&mut self.phi[i], &o.phi[i]);
            add_into(&mut self.info[i], &o.info[i]);
            add_into(&mut self.pos[i], &o.pos[i]);
            add_into(&mut self.vel[i], &o.vel[i]);
        }
    }

    /// The bound, with names `states` for the filter's states.
    pub fn report(&self, states: &[String]) -> PcrlbReport {
        let prior = if self.start_from_p0 {
            "filter P0; every run's start error is drawn from it".to_string()
        } else {
            "filter P0; the runs' start errors come from the scenario's dispersions, so the bound \
             holds where they match P0 (an efficiency below 1 means the runs started better than \
             P0 says)"
                .to_string()
        };
        let unavailable = |reason: String| PcrlbReport {
            available: false,
            reason: Some(reason),
            prior: prior.clone(),
            time_avg: BTreeMap::new(),
            final_: BTreeMap::new(),
            times_s: Vec::new(),
            series: BTreeMap::new(),
        };
        if let Some(r) = &self.unavailable {
            return unavailable(r.clone());
        }
        let n = self.dim;
        let k = self.count.iter().take_while(|c| **c > 0).count();
        if n == 0 || k == 0 {
            return unavailable("no epochs".into());
        }
        let mean = |m: &[f64], c: u64| DMatrix::from_row_slice(n, n, m) / c as f64;
        let steps: Vec<BoundStep> = (0..k)
            .map(|i| BoundStep {
                phi: mean(&self.phi[i], self.count[i]),
                q: DMatrix::zeros(n, n),
                info: mean(&self.info[i], self.count[i]),
            })
            .collect();
        let p0 = DMatrix::from_diagonal(&nalgebra::DVector::from_vec(self.p0_diag.clone()));
        let bounds = match pcrlb_recursion(&p0, &steps) {
            Ok(b) => b,
            Err(e) => return unavailable(e.to_string()),
        };
        let mut series: BTreeMap<String, Vec<f64>> = BTreeMap::new();
        let mut mean_sq_final: BTreeMap<String, f64> = BTreeMap::new();
        let trace_with = |p: &DMatrix<f64>, m: &[f64], c: u64| (p * mean(m, c)).trace().max(0.0);
        let ends: u64 = self.ends[..k].iter().sum();
        for (i, p) in bounds.iter().enumerate() {
            let mut put = |name: &str, var: f64| {
                series.entry(name.to_string()).or_default().push(var.sqrt());
                *mean_sq_final.entry(name.to_string()).or_default() += self.ends[i] as f64 * var;
            };
            for (s, name) in states.iter().enumerate().take(n) {
                put(name, p[(s, s)].max(0.0));
            }
            put("pos_m", trace_with(p, &self.pos[i], self.count[i]));
            put("vel_mps", trace_with(p, &self.vel[i], self.count[i]));
        }
        let time_avg = series
            .iter()
            .map(|(name, v)| (name.clone(), Some(v.iter().sum::<f64>() / v.len() as f64)))
            .collect();
        let final_ = mean_sq_final
            .into_iter()
            .map(|(name, s)| (name, (ends > 0).then(|| (s / ends as f64).sqrt())))
            .collect();
        PcrlbReport {
            available: true,
            reason: None,
            prior,
            time_avg,
            final_,
            times_s: self.times[..k].to_vec(),
            series,
        }
    }
}

/// Runs folded per parallel chunk by [`pcrlb_study`] (bounds the memory of the per-epoch
/// matrices held at once).
const STUDY_CHUNK: usize = 64;

/// The scenario's PCRLB without any filter: `runs` truth runs of master seed `seed`, drawn as a
/// trade with that seed draws them (`entrynav observe --pcrlb`). Runs are recorded in parallel
/// and folded in run order, so the result does not depend on the thread count.
pub fn pcrlb_study(scenario: &Scenario, seed: u64, runs: usize) -> Result<PcrlbReport, TradeError> {
    let mut sums = BoundSums::new(scenario);
    for start in (0..runs).step_by(STUDY_CHUNK) {
        let end = (start + STUDY_CHUNK).min(runs);
        let chunk: Result<Vec<BoundRun>, RunError> = (start..end)
            .into_par_iter()
            .map(|run| record_run(scenario, seed, run).map(|rec| bound_run(scenario, &rec)))
            .collect();
        sums.add_runs(&chunk?);
    }
    Ok(sums.report(&state_names(scenario)))
}
