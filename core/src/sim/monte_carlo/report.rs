//! The Monte Carlo report of one filter: summary statistics (the `trade` JSON), the deployment
//! ellipse and the time series behind the CSV files and plots. Built by
//! [`FilterAccumulator::report`](super::metrics::FilterAccumulator::report).

use super::consistency::Consistency;
use super::gate_stats::GatingSummary;
use super::metrics::{FilterAccumulator, FinalRow, RunProblem};
use super::moments::{EpochSums, FinalSums, Moments};
use crate::sim::bounds::pcrlb_sums::PcrlbReport;
use serde::Serialize;
use std::collections::BTreeMap;

/// 3σ error ellipse of the deployment point in the downrange/crossrange plane.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Ellipse {
    /// Mean downrange error \[km\].
    pub mean_downrange_km: f64,
    /// Mean crossrange error \[km\].
    pub mean_crossrange_km: f64,
    /// 3σ semi-major axis \[km\].
    pub semi_major_km: f64,
    /// 3σ semi-minor axis \[km\].
    pub semi_minor_km: f64,
    /// Angle of the major axis from the downrange axis toward crossrange \[deg\].
    pub orientation_deg: f64,
}

impl Ellipse {
    /// The ellipse from the sums (Σd, Σc, Σd², Σc², Σdc) of `n` downrange/crossrange errors \[m\].
    pub(crate) fn from_sums(s: &[f64; 5], n: u64) -> Option<Ellipse> {
        if n < 2 {
            return None;
        }
        let nf = n as f64;
        let (md, mc) = (s[0] / nf, s[1] / nf);
        let cdd = (s[2] - nf * md * md) / (nf - 1.0);
        let ccc = (s[3] - nf * mc * mc) / (nf - 1.0);
        let cdc = (s[4] - nf * md * mc) / (nf - 1.0);
        let tr = cdd + ccc;
        let disc = (((cdd - ccc) * 0.5).powi(2) + cdc * cdc).sqrt();
        let (l1, l2) = (tr * 0.5 + disc, (tr * 0.5 - disc).max(0.0));
        Some(Ellipse {
            mean_downrange_km: md / 1e3,
            mean_crossrange_km: mc / 1e3,
            semi_major_km: 3.0 * l1.sqrt() / 1e3,
            semi_minor_km: 3.0 * l2.sqrt() / 1e3,
            orientation_deg: (0.5 * (2.0 * cdc).atan2(cdd - ccc)).to_degrees(),
        })
    }
}

/// Names of the local-frame position errors in the RMSE tables: along the true heading, across
/// it in the local horizontal plane, and radial \[m\].
pub const LOCAL_POSITION_ERRORS: [&str; 3] = ["downrange_m", "crossrange_m", "up_m"];

/// Time series of a filter's Monte Carlo statistics (for CSV and plots; not in the JSON summary).
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct Series {
    /// Epoch times \[s\].
    pub times_s: Vec<f64>,
    /// RMSE per epoch and state.
    pub rmse: Vec<Vec<Option<f64>>>,
    /// Mean predicted 1σ per epoch and state.
    pub sigma_mean: Vec<Vec<Option<f64>>>,
    /// Mean error (bias) per epoch and state.
    pub bias: Vec<Vec<Option<f64>>>,
    /// Position-error RMS \[m\].
    pub pos_rmse_m: Vec<Option<f64>>,
    /// RMSE per epoch of the local position errors, in the order of [`LOCAL_POSITION_ERRORS`]
    /// (downrange, crossrange, up) \[m\].
    pub local_rmse_m: Vec<Vec<Option<f64>>>,
    /// Velocity-error RMS [m/s].
    pub vel_rmse_mps: Vec<Option<f64>>,
    /// NEES averaged over runs (all states with truth).
    pub nees_mean: Vec<Option<f64>>,
    /// NEES of the kinematic states averaged over runs.
    pub nees_kinematic_mean: Vec<Option<f64>>,
    /// NIS averaged over the runs that measured.
    pub nis_mean: Vec<Option<f64>>,
    /// Per channel slot (the trade's `channels` order), its ν²/s term averaged over the runs
    /// at each epoch.
    pub channel_nis_mean: Vec<Vec<Option<f64>>>,
    /// RMS relative error of the density profile at the true altitude [%] (seed 001 Fig. 10).
    pub density_rms_pct: Vec<Option<f64>>,
    /// Mean relative error of the density profile at the true altitude [%].
    pub density_mean_pct: Vec<Option<f64>>,
    /// RMS relative error of the density at the filter's estimate [%].
    pub density_at_estimate_rms_pct: Vec<Option<f64>>,
    /// Mean fusion weights / model probabilities.
    pub weights_mean: Vec<Vec<f64>>,
}

/// Monte Carlo summary of one filter (`Default`: no runs, for building one in a test).
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct FilterReport {
    /// Filter name.
    pub name: String,
    /// Runs folded in.
    pub runs: u64,
    /// Time-averaged RMSE per state (SI; `pos_m`, `vel_mps` are error-vector norms).
    pub rmse_time_avg: BTreeMap<String, Option<f64>>,
    /// Seed 001 eq. 69 as printed: time average of the mean |error|.
    pub mae_time_avg_eq69: BTreeMap<String, Option<f64>>,
    /// RMSE at the final epoch (parachute deployment).
    pub rmse_final: BTreeMap<String, Option<f64>>,
    /// Mean error at the final epoch.
    pub final_error_mean: BTreeMap<String, Option<f64>>,
    /// Per state, the fraction of (run, epoch) samples whose error is inside the filter's own ±3σ
    /// (≈ 0.997 for a consistent Gaussian filter; seed 000 Fig. 6 judges consistency this way).
    pub within_3sigma_frac: BTreeMap<String, Option<f64>>,
    /// NEES and NIS: averages, χ² bounds, fractions inside, NIS per channel.
    #[serde(flatten)]
    pub consistency: Consistency,
    /// Runs that stopped on a numerical failure.
    pub failed: u64,
    /// Runs that completed with their final NEES above 100 × dof.
    pub diverged: u64,
    /// The bad runs of this filter, failed (`kind: numerical`) and diverged (`kind: nees`): the
    /// first 20 of each kind in run order (run index, time, kind, reason); `failed` and
    /// `diverged` count all of them. Every run's final state is in `--csv-dir`'s
    /// `{scenario}_final_errors.csv`.
    pub failures: Vec<RunProblem>,
    /// Mean CPU time per filter step \[µs\] (wall clock; not reproducible bit for bit, so not
    /// serialised with the statistics: the CLI writes it to the summary's `timing` block).
    #[serde(skip)]
    pub us_per_step: f64,
    /// Density RMSPE (seed 001 eq. 70, Table 6) [%] for filters that estimate density: the
    /// filter's density profile at the true altitude against the true density.
    pub density_rmspe_pct: Option<f64>,
    /// The same statistic for the filter's density at its own estimate x̂ [%].
    pub density_at_estimate_rmspe_pct: Option<f64>,
    /// What the innovation gate did (`[filter.gating]`; absent without a gate).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub gating: Option<GatingSummary>,
    /// 3σ deployment-point ellipse.
    pub ellipse_km: Option<Ellipse>,
    /// RMSE / PCRLB per state and for `pos_m`/`vel_mps`, time-averaged (1 is the best any
    /// estimator could do; empty when the scenario has no bound).
    pub efficiency_time_avg: BTreeMap<String, Option<f64>>,
    /// RMSE / PCRLB at the final epoch.
    pub efficiency_final: BTreeMap<String, Option<f64>>,
    /// Time series (CSV, plots).
    #[serde(skip)]
    pub series: Series,
    /// Every run's final errors and status, in run order (CSV only).
    #[serde(skip)]
    pub final_errors: Vec<FinalRow>,
}

impl FilterReport {
    /// Fill the efficiencies RMSE / PCRLB from the scenario's `bound`.
    pub fn set_efficiency(&mut self, bound: &PcrlbReport) {
        let ratio = |rmse: &BTreeMap<String, Option<f64>>, b: &BTreeMap<String, Option<f64>>| {
            rmse.iter()
                .map(|(k, r)| {
                    let e = match (r, b.get(k).copied().flatten()) {
                        (Some(r), Some(b)) if b > 0.0 => Some(r / b),
                        _ => None,
                    };
                    (k.clone(), e)
                })
                .collect()
        };
        self.efficiency_time_avg = ratio(&self.rmse_time_avg, &bound.time_avg);
        self.efficiency_final = ratio(&self.rmse_final, &bound.final_);
    }
}

/// Time average of the epochs that have a value.
fn time_avg(v: &[Option<f64>]) -> Option<f64> {
    let f: Vec<f64> = v.iter().flatten().copied().collect();
    (!f.is_empty()).then(|| f.iter().sum::<f64>() / f.len() as f64)
}

/// Per-state statistics over epochs: the RMSE, mean σ and bias series, and the time averages of
/// the RMSE and of the mean |error| (seed 001 eq. 69), keyed by state name.
struct StateStats {
    rmse: Vec<Vec<Option<f64>>>,
    sigma: Vec<Vec<Option<f64>>>,
    bias: Vec<Vec<Option<f64>>>,
    rmse_avg: BTreeMap<String, Option<f64>>,
    mae_avg: BTreeMap<String, Option<f64>>,
}

fn state_stats(epochs: &[EpochSums], states: &[String]) -> StateStats {
    let nk = epochs.len();
    let mut out = StateStats {
        rmse: vec![vec![None; states.len()]; nk],
        sigma: vec![vec![None; states.len()]; nk],
        bias: vec![vec![None; states.len()]; nk],
        rmse_avg: BTreeMap::new(),
        mae_avg: BTreeMap::new(),
    };
    for (i, s) in states.iter().enumerate() {
        let (mut acc_rmse, mut acc_mae, mut n) = (0.0, 0.0, 0usize);
        for (k, e) in epochs.iter().enumerate() {
            let Some(st) = e.states.get(i).filter(|st| st.err.n > 0) else {
                continue;
            };
            let c = st.err.n as f64;
            let rmse = (st.err.sum_sq / c).sqrt();
            out.rmse[k][i] = Some(rmse);
            out.sigma[k][i] = Some(st.sigma / c);
            out.bias[k][i] = Some(st.err.sum / c);
            acc_rmse += rmse;
            acc_mae += st.err.sum_abs / c;
            n += 1;
        }
        out.rmse_avg
            .insert(s.clone(), (n > 0).then(|| acc_rmse / n as f64));
        out.mae_avg
            .insert(s.clone(), (n > 0).then(|| acc_mae / n as f64));
    }
    out
}

/// RMSE at the final epoch per state, for `pos_m`/`vel_mps` and the local position errors.
fn final_rmse(f: &FinalSums, states: &[String]) -> BTreeMap<String, Option<f64>> {
    let mut out: BTreeMap<String, Option<f64>> = states
        .iter()
        .enumerate()
        .map(|(i, s)| (s.clone(), f.states.get(i).and_then(Moments::rms)))
        .collect();
    out.insert("pos_m".into(), f.rms_of(f.pos_sq));
    out.insert("vel_mps".into(), f.rms_of(f.vel_sq));
    for (name, sq) in LOCAL_POSITION_ERRORS
        .iter()
        .zip([f.dr_cr[2], f.dr_cr[3], f.up_sq])
    {
        out.insert((*name).into(), f.rms_of(sq));
    }
    out
}

/// Seed 001 eq. 70: the time average of the per-epoch mean |relative error| [%].
fn rmspe_pct(epochs: &[EpochSums], of: impl Fn(&EpochSums) -> &Moments) -> Option<f64> {
    let per_epoch: Vec<f64> = epochs.iter().filter_map(|e| of(e).mean_abs()).collect();
    (!per_epoch.is_empty()).then(|| 100.0 * per_epoch.iter().sum::<f64>() / per_epoch.len() as f64)
}

impl FilterAccumulator {
    /// Summarise into a report for the filter `name` with state names `states` and channel names
    /// `channels`.
    pub fn report(&self, name: &str, states: &[String], channels: &[String]) -> FilterReport {
        let epochs = &self.epochs;
        let per_epoch = |f: &dyn Fn(&EpochSums) -> Option<f64>| -> Vec<Option<f64>> {
            epochs.iter().map(f).collect()
        };
        let stats = state_stats(epochs, states);
        let pos_series = per_epoch(&|e| e.rms_of(e.pos_sq));
        let vel_series = per_epoch(&|e| e.rms_of(e.vel_sq));
        let local_series: Vec<Vec<Option<f64>>> = (0..3)
            .map(|c| per_epoch(&|e| e.rms_of(e.local_sq[c])))
            .collect();
        let mut rmse_avg = stats.rmse_avg;
        rmse_avg.insert("pos_m".into(), time_avg(&pos_series));
        rmse_avg.insert("vel_mps".into(), time_avg(&vel_series));
        for (name, series) in LOCAL_POSITION_ERRORS.iter().zip(&local_series) {
            rmse_avg.insert((*name).into(), time_avg(series));
        }
        let fin = &self.final_sums;
        let within_3sigma_frac = states
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let (inside, n) = self.within_3sigma.get(i).copied().unwrap_or((0, 0));
                (s.clone(), (n > 0).then(|| inside as f64 / n as f64))
            })
            .collect();
        FilterReport {
            name: name.to_string(),
            within_3sigma_frac,
            runs: self.runs,
            rmse_time_avg: rmse_avg,
            mae_time_avg_eq69: stats.mae_avg,
            rmse_final: final_rmse(fin, states),
            final_error_mean: states
                .iter()
                .enumerate()
                .map(|(i, s)| (s.clone(), fin.states.get(i).and_then(Moments::mean)))
                .collect(),
            consistency: self.consistency.report(channels),
            failed: self.failed,
            diverged: self.diverged,
            failures: self.problems.clone(),
            us_per_step: if self.steps > 0 {
                self.filter_ns as f64 / self.steps as f64 / 1e3
            } else {
                0.0
            },
            density_rmspe_pct: rmspe_pct(epochs, |e| &e.density),
            density_at_estimate_rmspe_pct: rmspe_pct(epochs, |e| &e.density_at_estimate),
            gating: self.gate.report(channels),
            ellipse_km: Ellipse::from_sums(&fin.dr_cr, fin.runs),
            efficiency_time_avg: BTreeMap::new(),
            efficiency_final: BTreeMap::new(),
            series: Series {
                times_s: self.times.clone(),
                rmse: stats.rmse,
                sigma_mean: stats.sigma,
                bias: stats.bias,
                pos_rmse_m: pos_series,
                local_rmse_m: local_series,
                vel_rmse_mps: vel_series,
                nees_mean: self.consistency.nees_series(),
                nees_kinematic_mean: self.consistency.nees_kinematic_series(),
                nis_mean: self.consistency.nis_series(),
                channel_nis_mean: self.consistency.channel_nis_series(),
                density_rms_pct: per_epoch(&|e| e.density.rms().map(|v| 100.0 * v)),
                density_mean_pct: per_epoch(&|e| e.density.mean().map(|v| 100.0 * v)),
                density_at_estimate_rms_pct: per_epoch(&|e| {
                    e.density_at_estimate.rms().map(|v| 100.0 * v)
                }),
                weights_mean: epochs
                    .iter()
                    .map(|e| e.weights.iter().map(|w| w / e.runs.max(1) as f64).collect())
                    .collect(),
            },
            final_errors: self.finals.clone(),
        }
    }
}
