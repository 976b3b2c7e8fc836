//! Monte Carlo metrics: per-run records, accumulators folded in run order, and the report.
//!
//! * RMSE vs time per state, and its time average (seed 001 eq. 69 prints the time average of the
//!   per-epoch mean of √(e²), i.e. a mean *absolute* error; we report that as `mae_time_avg_eq69`
//!   and the time average of the true RMSE as `rmse_time_avg`).
//! * Density RMSPE (seed 001 eq. 70, same mean-of-|·| form) for filters that estimate density, in
//!   two readings: the filter's density *profile* at the true altitude against the true density
//!   (`density_rmspe_pct`, Table 6's reading: how well the onboard model matches the atmosphere),
//!   and the filter's density at its own estimate x̂ (`density_at_estimate_rmspe_pct`: what the
//!   dynamics see; small for every filter that processes density-sensitive measurements).
//! * Final-epoch (parachute deployment) error mean/covariance and the 3σ downrange/crossrange ellipse.
//! * NEES per epoch averaged over runs, ANEES, with two-sided 95 % χ² bounds.

use serde::Serialize;
use std::collections::BTreeMap;

/// What one filter produced at one epoch of one run.
#[derive(Debug, Clone, PartialEq)]
pub struct EpochRecord {
    /// Estimation error per state (NaN where the state has no truth).
    pub err: Vec<f64>,
    /// Predicted 1σ per state.
    pub sigma: Vec<f64>,
    /// Position error norm [m] and velocity error norm [m/s].
    pub pos_vel_err: (f64, f64),
    /// NEES eᵀP⁻¹e over the states with truth, and its degrees of freedom.
    pub nees: Option<(f64, usize)>,
    /// Density relative error (ρ̂(h) − ρ(h))/ρ(h) of the filter's profile at the true altitude h,
    /// for filters that estimate density.
    pub density_rel_err: Option<f64>,
    /// Density relative error (ρ̂(x̂) − ρ(x))/ρ(x) at the filter's own estimate.
    pub density_at_estimate_rel_err: Option<f64>,
    /// Fusion weights / model probabilities.
    pub weights: Option<Vec<f64>>,
}

/// Final-epoch quantities of one run.
#[derive(Debug, Clone, PartialEq)]
pub struct FinalRecord {
    /// Downrange and crossrange position error [m] (along / across the true heading).
    pub downrange_crossrange: (f64, f64),
}

/// Everything one filter produced in one run.
#[derive(Debug, Clone, PartialEq)]
pub struct RunRecord {
    /// Per-epoch records, in time order.
    pub epochs: Vec<EpochRecord>,
    /// Epoch times [s].
    pub times: Vec<f64>,
    /// Final-epoch record (None if the filter failed).
    pub final_: Option<FinalRecord>,
    /// Numerical failure, if any: (time, reason).
    pub failure: Option<(f64, String)>,
    /// CPU time in the filter [ns] and steps.
    pub filter_ns: u128,
    /// Filter steps.
    pub steps: usize,
}

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

/// Sums over runs, folded in run-index order so results do not depend on thread count.
///
/// Serialisable so that shards of a study can be merged exactly (`trade merge`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, serde::Deserialize)]
pub struct FilterAccumulator {
    times: Vec<f64>,
    count: Vec<Vec<u64>>,
    sum_sq: Vec<Vec<f64>>,
    sum_abs: Vec<Vec<f64>>,
    sum_err: Vec<Vec<f64>>,
    sum_sigma: Vec<Vec<f64>>,
    sum_pos_sq: Vec<f64>,
    sum_vel_sq: Vec<f64>,
    n_epoch: Vec<u64>,
    nees_sum: Vec<f64>,
    nees_n: Vec<u64>,
    nees_dof: usize,
    dens_abs: Vec<f64>,
    dens_sq: Vec<f64>,
    dens_n: Vec<u64>,
    #[serde(default)]
    dens_sum: Vec<f64>,
    #[serde(default)]
    dest_abs: Vec<f64>,
    #[serde(default)]
    dest_sq: Vec<f64>,
    #[serde(default)]
    dest_n: Vec<u64>,
    weights_sum: Vec<Vec<f64>>,
    within3: Vec<u64>,
    within3_n: Vec<u64>,
    final_n: u64,
    final_sum_err: Vec<f64>,
    final_sum_sq: Vec<f64>,
    final_count: Vec<u64>,
    final_pos_sq: f64,
    final_vel_sq: f64,
    dr_cr: [f64; 5],
    diverged: u64,
    failures: Vec<(usize, f64, String)>,
    filter_ns: u128,
    steps: u64,
    runs: u64,
}

fn grow<T: Clone + Default>(v: &mut Vec<T>, n: usize) {
    if v.len() < n {
        v.resize(n, T::default());
    }
}

fn add_vec<T: Copy + Default + std::ops::AddAssign>(a: &mut Vec<T>, b: &[T]) {
    grow(a, b.len());
    for (x, y) in a.iter_mut().zip(b) {
        *x += *y;
    }
}

fn add_vec2<T: Copy + Default + std::ops::AddAssign>(a: &mut Vec<Vec<T>>, b: &[Vec<T>]) {
    grow(a, b.len());
    for (x, y) in a.iter_mut().zip(b) {
        add_vec(x, y);
    }
}

impl FilterAccumulator {
    /// Add another accumulator's sums (blocks are merged in block order, so a sharded study
    /// merged afterwards gives exactly the single-process sums).
    pub fn merge(&mut self, o: &FilterAccumulator) {
        if self.times.len() < o.times.len() {
            self.times = o.times.clone();
        }
        add_vec2(&mut self.count, &o.count);
        add_vec2(&mut self.sum_sq, &o.sum_sq);
        add_vec2(&mut self.sum_abs, &o.sum_abs);
        add_vec2(&mut self.sum_err, &o.sum_err);
        add_vec2(&mut self.sum_sigma, &o.sum_sigma);
        add_vec(&mut self.sum_pos_sq, &o.sum_pos_sq);
        add_vec(&mut self.sum_vel_sq, &o.sum_vel_sq);
        add_vec(&mut self.n_epoch, &o.n_epoch);
        add_vec(&mut self.nees_sum, &o.nees_sum);
        add_vec(&mut self.nees_n, &o.nees_n);
        self.nees_dof = self.nees_dof.max(o.nees_dof);
        add_vec(&mut self.dens_abs, &o.dens_abs);
        add_vec(&mut self.dens_sq, &o.dens_sq);
        add_vec(&mut self.dens_n, &o.dens_n);
        add_vec(&mut self.dens_sum, &o.dens_sum);
        add_vec(&mut self.dest_abs, &o.dest_abs);
        add_vec(&mut self.dest_sq, &o.dest_sq);
        add_vec(&mut self.dest_n, &o.dest_n);
        add_vec2(&mut self.weights_sum, &o.weights_sum);
        add_vec(&mut self.within3, &o.within3);
        add_vec(&mut self.within3_n, &o.within3_n);
        self.final_n += o.final_n;
        add_vec(&mut self.final_sum_err, &o.final_sum_err);
        add_vec(&mut self.final_sum_sq, &o.final_sum_sq);
        add_vec(&mut self.final_count, &o.final_count);
        self.final_pos_sq += o.final_pos_sq;
        self.final_vel_sq += o.final_vel_sq;
        for (a, b) in self.dr_cr.iter_mut().zip(o.dr_cr) {
            *a += b;
        }
        self.diverged += o.diverged;
        for f in &o.failures {
            if self.failures.len() < 10 {
                self.failures.push(f.clone());
            }
        }
        self.filter_ns += o.filter_ns;
        self.steps += o.steps;
        self.runs += o.runs;
    }

    /// Fold one run in (call in run-index order).
    pub fn add(&mut self, run_index: usize, rec: &RunRecord) {
        self.runs += 1;
        self.filter_ns += rec.filter_ns;
        self.steps += rec.steps as u64;
        let n_ep = rec.epochs.len();
        if self.times.len() < rec.times.len() {
            self.times = rec.times.clone();
        }
        for v in [
            &mut self.sum_pos_sq,
            &mut self.sum_vel_sq,
            &mut self.nees_sum,
            &mut self.dens_abs,
            &mut self.dens_sq,
            &mut self.dens_sum,
            &mut self.dest_abs,
            &mut self.dest_sq,
        ] {
            grow(v, n_ep);
        }
        for v in [
            &mut self.n_epoch,
            &mut self.nees_n,
            &mut self.dens_n,
            &mut self.dest_n,
        ] {
            grow(v, n_ep);
        }
        grow(&mut self.count, n_ep);
        for v in [
            &mut self.sum_sq,
            &mut self.sum_abs,
            &mut self.sum_err,
            &mut self.sum_sigma,
            &mut self.weights_sum,
        ] {
            grow(v, n_ep);
        }
        for (k, e) in rec.epochs.iter().enumerate() {
            let n = e.err.len();
            grow(&mut self.count[k], n);
            for v in [
                &mut self.sum_sq[k],
                &mut self.sum_abs[k],
                &mut self.sum_err[k],
                &mut self.sum_sigma[k],
            ] {
                grow(v, n);
            }
            grow(&mut self.within3, n);
            grow(&mut self.within3_n, n);
            for i in 0..n {
                if e.err[i].is_finite() {
                    self.within3_n[i] += 1;
                    if e.err[i].abs() <= 3.0 * e.sigma[i] {
                        self.within3[i] += 1;
                    }
                    self.count[k][i] += 1;
                    self.sum_sq[k][i] += e.err[i] * e.err[i];
                    self.sum_abs[k][i] += e.err[i].abs();
                    self.sum_err[k][i] += e.err[i];
                    self.sum_sigma[k][i] += e.sigma[i];
                }
            }
            self.n_epoch[k] += 1;
            self.sum_pos_sq[k] += e.pos_vel_err.0 * e.pos_vel_err.0;
            self.sum_vel_sq[k] += e.pos_vel_err.1 * e.pos_vel_err.1;
            if let Some((nees, dof)) = e.nees {
                self.nees_sum[k] += nees;
                self.nees_n[k] += 1;
                self.nees_dof = dof;
            }
            if let Some(d) = e.density_rel_err {
                self.dens_abs[k] += d.abs();
                self.dens_sq[k] += d * d;
                self.dens_sum[k] += d;
                self.dens_n[k] += 1;
            }
            if let Some(d) = e.density_at_estimate_rel_err {
                self.dest_abs[k] += d.abs();
                self.dest_sq[k] += d * d;
                self.dest_n[k] += 1;
            }
            if let Some(w) = &e.weights {
                grow(&mut self.weights_sum[k], w.len());
                for (j, wj) in w.iter().enumerate() {
                    self.weights_sum[k][j] += wj;
                }
            }
        }
        let last_nees = rec.epochs.last().and_then(|e| e.nees);
        let blew_up = last_nees.is_some_and(|(v, dof)| v > 100.0 * dof as f64);
        if let Some((t, reason)) = &rec.failure {
            self.diverged += 1;
            if self.failures.len() < 10 {
                self.failures.push((run_index, *t, reason.clone()));
            }
        } else if blew_up {
            self.diverged += 1;
        }
        if let (Some(f), Some(last)) = (&rec.final_, rec.epochs.last()) {
            self.final_n += 1;
            let n = last.err.len();
            for v in [&mut self.final_sum_err, &mut self.final_sum_sq] {
                grow(v, n);
            }
            grow(&mut self.final_count, n);
            for i in 0..n {
                if last.err[i].is_finite() {
                    self.final_sum_err[i] += last.err[i];
                    self.final_sum_sq[i] += last.err[i] * last.err[i];
                    self.final_count[i] += 1;
                }
            }
            self.final_pos_sq += last.pos_vel_err.0 * last.pos_vel_err.0;
            self.final_vel_sq += last.pos_vel_err.1 * last.pos_vel_err.1;
            let (d, c) = f.downrange_crossrange;
            for (s, v) in self.dr_cr.iter_mut().zip([d, c, d * d, c * c, d * c]) {
                *s += v;
            }
        }
    }

    /// Summarise into a report for the filter `name` with state names `states`.
    pub fn report(&self, name: &str, states: &[String]) -> FilterReport {
        let nk = self.times.len();
        let safe = |s: f64, n: u64| if n > 0 { Some(s / n as f64) } else { None };
        let mut rmse_series = vec![vec![None; states.len()]; nk];
        let mut sigma_series = vec![vec![None; states.len()]; nk];
        let mut bias_series = vec![vec![None; states.len()]; nk];
        let mut rmse_avg = BTreeMap::new();
        let mut mae_avg = BTreeMap::new();
        for (i, s) in states.iter().enumerate() {
            let (mut acc_rmse, mut acc_mae, mut n) = (0.0, 0.0, 0usize);
            for k in 0..nk {
                let c = self
                    .count
                    .get(k)
                    .and_then(|v| v.get(i))
                    .copied()
                    .unwrap_or(0);
                if c == 0 {
                    continue;
                }
                let rmse = (self.sum_sq[k][i] / c as f64).sqrt();
                rmse_series[k][i] = Some(rmse);
                sigma_series[k][i] = Some(self.sum_sigma[k][i] / c as f64);
                bias_series[k][i] = Some(self.sum_err[k][i] / c as f64);
                acc_rmse += rmse;
                acc_mae += self.sum_abs[k][i] / c as f64;
                n += 1;
            }
            rmse_avg.insert(s.clone(), (n > 0).then(|| acc_rmse / n as f64));
            mae_avg.insert(s.clone(), (n > 0).then(|| acc_mae / n as f64));
        }
        let pos_series: Vec<Option<f64>> = (0..nk)
            .map(|k| safe(self.sum_pos_sq[k], self.n_epoch[k]).map(f64::sqrt))
            .collect();
        let vel_series: Vec<Option<f64>> = (0..nk)
            .map(|k| safe(self.sum_vel_sq[k], self.n_epoch[k]).map(f64::sqrt))
            .collect();
        let avg = |v: &[Option<f64>]| {
            let f: Vec<f64> = v.iter().flatten().copied().collect();
            (!f.is_empty()).then(|| f.iter().sum::<f64>() / f.len() as f64)
        };
        rmse_avg.insert("pos_m".into(), avg(&pos_series));
        rmse_avg.insert("vel_mps".into(), avg(&vel_series));
        let mut rmse_final = BTreeMap::new();
        for (i, s) in states.iter().enumerate() {
            let c = self.final_count.get(i).copied().unwrap_or(0);
            rmse_final.insert(
                s.clone(),
                (c > 0).then(|| (self.final_sum_sq[i] / c as f64).sqrt()),
            );
        }
        rmse_final.insert(
            "pos_m".into(),
            (self.final_n > 0).then(|| (self.final_pos_sq / self.final_n as f64).sqrt()),
        );
        rmse_final.insert(
            "vel_mps".into(),
            (self.final_n > 0).then(|| (self.final_vel_sq / self.final_n as f64).sqrt()),
        );

        let nees_series: Vec<Option<f64>> = (0..nk)
            .map(|k| safe(self.nees_sum[k], self.nees_n[k]))
            .collect();
        let runs_at_end = self.nees_n.iter().copied().max().unwrap_or(0) as usize;
        let bounds = nees_bounds_95(self.nees_dof, runs_at_end.max(1));
        let finite_nees: Vec<f64> = nees_series.iter().flatten().copied().collect();
        let anees = (!finite_nees.is_empty())
            .then(|| finite_nees.iter().sum::<f64>() / finite_nees.len() as f64);
        let in_bounds = if finite_nees.is_empty() {
            None
        } else {
            Some(
                finite_nees
                    .iter()
                    .filter(|v| **v >= bounds.0 && **v <= bounds.1)
                    .count() as f64
                    / finite_nees.len() as f64,
            )
        };
        let dens: Vec<f64> = (0..nk)
            .filter_map(|k| safe(self.dens_abs[k], self.dens_n[k]))
            .collect();
        let density_rmspe_pct =
            (!dens.is_empty()).then(|| 100.0 * dens.iter().sum::<f64>() / dens.len() as f64);
        let density_series: Vec<Option<f64>> = (0..nk)
            .map(|k| safe(self.dens_sq[k], self.dens_n[k]).map(|v| 100.0 * v.sqrt()))
            .collect();
        let density_bias_series: Vec<Option<f64>> = (0..nk)
            .map(|k| {
                let sum = self.dens_sum.get(k).copied().unwrap_or(0.0);
                safe(sum, self.dens_n[k]).map(|v| 100.0 * v)
            })
            .collect();
        let dest: Vec<f64> = (0..nk)
            .filter_map(|k| safe(self.dest_abs[k], self.dest_n[k]))
            .collect();
        let density_at_estimate_rmspe_pct =
            (!dest.is_empty()).then(|| 100.0 * dest.iter().sum::<f64>() / dest.len() as f64);
        let density_at_estimate_series: Vec<Option<f64>> = (0..nk)
            .map(|k| safe(self.dest_sq[k], self.dest_n[k]).map(|v| 100.0 * v.sqrt()))
            .collect();
        let weights_series: Vec<Vec<f64>> = (0..nk)
            .map(|k| {
                self.weights_sum[k]
                    .iter()
                    .map(|w| w / self.n_epoch[k].max(1) as f64)
                    .collect()
            })
            .collect();

        let within_3sigma_frac = states
            .iter()
            .enumerate()
            .map(|(i, s)| {
                let n = self.within3_n.get(i).copied().unwrap_or(0);
                (
                    s.clone(),
                    (n > 0).then(|| self.within3[i] as f64 / n as f64),
                )
            })
            .collect();
        FilterReport {
            name: name.to_string(),
            within_3sigma_frac,
            runs: self.runs,
            rmse_time_avg: rmse_avg,
            mae_time_avg_eq69: mae_avg,
            rmse_final,
            final_error_mean: states
                .iter()
                .enumerate()
                .map(|(i, s)| {
                    let c = self.final_count.get(i).copied().unwrap_or(0);
                    (s.clone(), (c > 0).then(|| self.final_sum_err[i] / c as f64))
                })
                .collect(),
            anees,
            nees_dof: self.nees_dof,
            nees_bounds_95: [bounds.0, bounds.1],
            nees_in_bounds_frac: in_bounds,
            diverged: self.diverged,
            failures: self
                .failures
                .iter()
                .map(|(r, t, m)| format!("run {r} at t = {t} s: {m}"))
                .collect(),
            us_per_step: if self.steps > 0 {
                self.filter_ns as f64 / self.steps as f64 / 1e3
            } else {
                0.0
            },
            density_rmspe_pct,
            density_at_estimate_rmspe_pct,
            ellipse_km: Ellipse::from_sums(&self.dr_cr, self.final_n),
            series: Series {
                times_s: self.times.clone(),
                rmse: rmse_series,
                sigma_mean: sigma_series,
                bias: bias_series,
                pos_rmse_m: pos_series,
                vel_rmse_mps: vel_series,
                nees_mean: nees_series,
                density_rms_pct: density_series,
                density_mean_pct: density_bias_series,
                density_at_estimate_rms_pct: density_at_estimate_series,
                weights_mean: weights_series,
            },
        }
    }
}

/// 3σ error ellipse of the deployment point in the downrange/crossrange plane.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Ellipse {
    /// Mean downrange error [km].
    pub mean_downrange_km: f64,
    /// Mean crossrange error [km].
    pub mean_crossrange_km: f64,
    /// 3σ semi-major axis [km].
    pub semi_major_km: f64,
    /// 3σ semi-minor axis [km].
    pub semi_minor_km: f64,
    /// Angle of the major axis from the downrange axis toward crossrange [deg].
    pub orientation_deg: f64,
}

impl Ellipse {
    fn from_sums(s: &[f64; 5], n: u64) -> Option<Ellipse> {
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

/// Time series of a filter's Monte Carlo statistics (for CSV and plots; not in the JSON summary).
#[derive(Debug, Clone, PartialEq, Serialize, Default)]
pub struct Series {
    /// Epoch times [s].
    pub times_s: Vec<f64>,
    /// RMSE per epoch and state.
    pub rmse: Vec<Vec<Option<f64>>>,
    /// Mean predicted 1σ per epoch and state.
    pub sigma_mean: Vec<Vec<Option<f64>>>,
    /// Mean error (bias) per epoch and state.
    pub bias: Vec<Vec<Option<f64>>>,
    /// Position-error RMS [m].
    pub pos_rmse_m: Vec<Option<f64>>,
    /// Velocity-error RMS [m/s].
    pub vel_rmse_mps: Vec<Option<f64>>,
    /// NEES averaged over runs.
    pub nees_mean: Vec<Option<f64>>,
    /// RMS relative error of the density profile at the true altitude [%] (seed 001 Fig. 10).
    pub density_rms_pct: Vec<Option<f64>>,
    /// Mean relative error of the density profile at the true altitude [%].
    pub density_mean_pct: Vec<Option<f64>>,
    /// RMS relative error of the density at the filter's estimate [%].
    pub density_at_estimate_rms_pct: Vec<Option<f64>>,
    /// Mean fusion weights / model probabilities.
    pub weights_mean: Vec<Vec<f64>>,
}

/// Monte Carlo summary of one filter.
#[derive(Debug, Clone, PartialEq, Serialize)]
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
    /// Average NEES over epochs (of the per-epoch mean over runs).
    pub anees: Option<f64>,
    /// Degrees of freedom of the NEES.
    pub nees_dof: usize,
    /// Two-sided 95 % bounds for the per-epoch mean NEES.
    pub nees_bounds_95: [f64; 2],
    /// Fraction of epochs whose mean NEES is inside the bounds.
    pub nees_in_bounds_frac: Option<f64>,
    /// Runs that failed numerically or ended with NEES > 100·dof.
    pub diverged: u64,
    /// Up to ten numerical failures, described.
    pub failures: Vec<String>,
    /// Mean CPU time per filter step [µs] (wall clock; not reproducible bit for bit).
    pub us_per_step: f64,
    /// Density RMSPE (seed 001 eq. 70, Table 6) [%] for filters that estimate density: the
    /// filter's density profile at the true altitude against the true density.
    pub density_rmspe_pct: Option<f64>,
    /// The same statistic for the filter's density at its own estimate x̂ [%].
    pub density_at_estimate_rmspe_pct: Option<f64>,
    /// 3σ deployment-point ellipse.
    pub ellipse_km: Option<Ellipse>,
    /// Time series (CSV, plots).
    #[serde(skip)]
    pub series: Series,
}

#[cfg(test)]
mod tests {
    use super::*;

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
