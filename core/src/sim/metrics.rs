//! Monte Carlo metrics: per-run records and the accumulators folded in run order (their summary,
//! [`FilterAccumulator::report`], is in [`super::report`]).
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
//! * NEES and NIS per epoch averaged over runs, with two-sided 95 % χ² bounds
//!   ([`super::consistency`]).
//! * Runs that went wrong, in two kinds: a **numerical failure** (the filter stopped: a
//!   covariance lost positive definiteness, a value became non-finite) and a **NEES divergence**
//!   (the run completed but its final NEES exceeds [`DIVERGENCE_NEES_PER_DOF`] × dof: the
//!   filter is confidently wrong).

use super::consistency::ConsistencySums;
use serde::Serialize;

/// A completed run whose final-epoch NEES exceeds this many times its degrees of freedom counts as
/// diverged (a consistent filter exceeds 100·dof with probability far below 1e-9).
pub const DIVERGENCE_NEES_PER_DOF: f64 = 100.0;

/// Runs kept in a report's list of problems, per kind.
const PROBLEMS_KEPT: usize = 20;

/// What went wrong in one run.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, serde::Deserialize)]
#[serde(rename_all = "kebab-case")]
pub enum ProblemKind {
    /// The filter stopped on a numerical failure.
    Numerical,
    /// The run completed with its final NEES above `DIVERGENCE_NEES_PER_DOF` × dof.
    Nees,
}

/// One run that failed or diverged.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct RunProblem {
    /// Run index (replay it with `trade --replay-run`).
    pub run: usize,
    /// Time of the failure, or of the first epoch whose NEES exceeded the threshold \[s\].
    pub t_s: f64,
    /// Which kind.
    pub kind: ProblemKind,
    /// What happened.
    pub reason: String,
}

/// What one filter produced at one epoch of one run.
#[derive(Debug, Clone, PartialEq)]
pub struct EpochRecord {
    /// Estimation error per state (NaN where the state has no truth).
    pub err: Vec<f64>,
    /// Predicted 1σ per state.
    pub sigma: Vec<f64>,
    /// Position error norm \[m\] and velocity error norm [m/s].
    pub pos_vel_err: (f64, f64),
    /// Position error in the local frame at the truth \[m\]: downrange (along the true heading),
    /// crossrange, up (radial).
    pub local_err: [f64; 3],
    /// NEES eᵀP⁻¹e over the states with truth, and its degrees of freedom.
    pub nees: Option<(f64, usize)>,
    /// NEES over the six kinematic states.
    pub nees_kinematic: Option<f64>,
    /// Per scalar measurement: channel slot and ν²/s.
    pub nis_terms: Vec<(usize, f64)>,
    /// Density relative error (ρ̂(h) − ρ(h))/ρ(h) of the filter's profile at the true altitude h,
    /// for filters that estimate density.
    pub density_rel_err: Option<f64>,
    /// Density relative error (ρ̂(x̂) − ρ(x))/ρ(x) at the filter's own estimate.
    pub density_at_estimate_rel_err: Option<f64>,
    /// Fusion weights / model probabilities.
    pub weights: Option<Vec<f64>>,
}

/// One run's outcome for one filter at its last epoch: a row of the `_final_errors.csv` file.
#[derive(Debug, Clone, PartialEq, Serialize, serde::Deserialize)]
pub struct FinalRow {
    /// Run index.
    pub run: usize,
    /// `ok`, `diverged` (final NEES above the threshold) or `failed` (numerical failure; the
    /// values are those of the last epoch before it, empty if there was none).
    pub status: String,
    /// Error per state at the last epoch (`None` where the state has no truth).
    pub err: Vec<Option<f64>>,
    /// Position error norm \[m\].
    pub pos_m: Option<f64>,
    /// Velocity error norm \[m/s\].
    pub vel_mps: Option<f64>,
    /// NEES at the last epoch.
    pub nees: Option<f64>,
    /// Downrange and crossrange position error at the last epoch \[m\] (as in the deployment
    /// ellipse); `None` without a last epoch or in shard files written before it existed.
    #[serde(default)]
    pub downrange_crossrange_m: Option<(f64, f64)>,
}

/// Final-epoch quantities of one run.
#[derive(Debug, Clone, PartialEq)]
pub struct FinalRecord {
    /// Downrange and crossrange position error \[m\] (along / across the true heading).
    pub downrange_crossrange: (f64, f64),
}

/// Everything one filter produced in one run.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RunRecord {
    /// Per-epoch records, in time order.
    pub epochs: Vec<EpochRecord>,
    /// Epoch times \[s\].
    pub times: Vec<f64>,
    /// Final-epoch record (None if the filter failed).
    pub final_: Option<FinalRecord>,
    /// Numerical failure, if any: (time, reason).
    pub failure: Option<(f64, String)>,
    /// CPU time in the filter \[ns\] and steps.
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
    pub(super) times: Vec<f64>,
    pub(super) count: Vec<Vec<u64>>,
    pub(super) sum_sq: Vec<Vec<f64>>,
    pub(super) sum_abs: Vec<Vec<f64>>,
    pub(super) sum_err: Vec<Vec<f64>>,
    pub(super) sum_sigma: Vec<Vec<f64>>,
    pub(super) sum_pos_sq: Vec<f64>,
    pub(super) sum_vel_sq: Vec<f64>,
    pub(super) n_epoch: Vec<u64>,
    pub(super) consistency: ConsistencySums,
    pub(super) dens_abs: Vec<f64>,
    pub(super) dens_sq: Vec<f64>,
    pub(super) dens_n: Vec<u64>,
    #[serde(default)]
    pub(super) dens_sum: Vec<f64>,
    #[serde(default)]
    pub(super) dest_abs: Vec<f64>,
    #[serde(default)]
    pub(super) dest_sq: Vec<f64>,
    #[serde(default)]
    pub(super) dest_n: Vec<u64>,
    pub(super) weights_sum: Vec<Vec<f64>>,
    pub(super) within3: Vec<u64>,
    pub(super) within3_n: Vec<u64>,
    pub(super) final_n: u64,
    pub(super) final_sum_err: Vec<f64>,
    pub(super) final_sum_sq: Vec<f64>,
    pub(super) final_count: Vec<u64>,
    pub(super) final_pos_sq: f64,
    pub(super) final_vel_sq: f64,
    pub(super) dr_cr: [f64; 5],
    /// Per epoch, Σ of squared downrange, crossrange and up errors.
    #[serde(default)]
    pub(super) sum_local_sq: Vec<[f64; 3]>,
    /// Σ of squared final up errors.
    #[serde(default)]
    pub(super) final_up_sq: f64,
    pub(super) failed: u64,
    pub(super) diverged: u64,
    pub(super) problems: Vec<RunProblem>,
    pub(super) filter_ns: u128,
    pub(super) steps: u64,
    pub(super) runs: u64,
    /// One row per run, in run order (the per-run final-error CSV).
    #[serde(default)]
    pub(super) finals: Vec<FinalRow>,
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
    fn keep(&mut self, p: RunProblem) {
        if self.problems.iter().filter(|q| q.kind == p.kind).count() < PROBLEMS_KEPT {
            self.problems.push(p);
        }
    }

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
        self.consistency.merge(&o.consistency);
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
        if self.sum_local_sq.len() < o.sum_local_sq.len() {
            self.sum_local_sq.resize(o.sum_local_sq.len(), [0.0; 3]);
        }
        for (a, b) in self.sum_local_sq.iter_mut().zip(&o.sum_local_sq) {
            for (x, y) in a.iter_mut().zip(b) {
                *x += y;
            }
        }
        self.final_up_sq += o.final_up_sq;
        self.failed += o.failed;
        self.diverged += o.diverged;
        for p in &o.problems {
            self.keep(p.clone());
        }
        self.filter_ns += o.filter_ns;
        self.steps += o.steps;
        self.runs += o.runs;
        self.finals.extend(o.finals.iter().cloned());
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
            &mut self.dens_abs,
            &mut self.dens_sq,
            &mut self.dens_sum,
            &mut self.dest_abs,
            &mut self.dest_sq,
        ] {
            grow(v, n_ep);
        }
        for v in [&mut self.n_epoch, &mut self.dens_n, &mut self.dest_n] {
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
            if self.sum_local_sq.len() <= k {
                self.sum_local_sq.resize(k + 1, [0.0; 3]);
            }
            for (s, v) in self.sum_local_sq[k].iter_mut().zip(e.local_err) {
                *s += v * v;
            }
            self.sum_pos_sq[k] += e.pos_vel_err.0 * e.pos_vel_err.0;
            self.sum_vel_sq[k] += e.pos_vel_err.1 * e.pos_vel_err.1;
            self.consistency.add_epoch(k, e);
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
        let exceeds = |e: &EpochRecord| {
            e.nees
                .is_some_and(|(v, dof)| v > DIVERGENCE_NEES_PER_DOF * dof as f64)
        };
        let last = rec.epochs.last();
        let status = if rec.failure.is_some() {
            "failed"
        } else if last.is_some_and(exceeds) {
            "diverged"
        } else {
            "ok"
        };
        self.finals.push(FinalRow {
            run: run_index,
            status: status.into(),
            err: last.map_or_else(Vec::new, |e| {
                e.err.iter().map(|v| v.is_finite().then_some(*v)).collect()
            }),
            pos_m: last.map(|e| e.pos_vel_err.0),
            vel_mps: last.map(|e| e.pos_vel_err.1),
            nees: last.and_then(|e| e.nees).map(|(v, _)| v),
            downrange_crossrange_m: rec.final_.as_ref().map(|f| f.downrange_crossrange),
        });
        if let Some((t, reason)) = &rec.failure {
            self.failed += 1;
            self.keep(RunProblem {
                run: run_index,
                t_s: *t,
                kind: ProblemKind::Numerical,
                reason: reason.clone(),
            });
        } else if let Some(last) = rec.epochs.last().filter(|e| exceeds(e)) {
            self.diverged += 1;
            let first = rec.epochs.iter().position(exceeds).unwrap_or(0);
            let (nees, dof) = last.nees.unwrap_or((f64::NAN, 0));
            self.keep(RunProblem {
                run: run_index,
                t_s: rec.times.get(first).copied().unwrap_or(f64::NAN),
                kind: ProblemKind::Nees,
                reason: format!(
                    "final NEES {nees:.4e} > {DIVERGENCE_NEES_PER_DOF} x {dof} dof (first above at this time)"
                ),
            });
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
            self.final_up_sq += last.local_err[2] * last.local_err[2];
            let (d, c) = f.downrange_crossrange;
            for (s, v) in self.dr_cr.iter_mut().zip([d, c, d * d, c * c, d * c]) {
                *s += v;
            }
        }
    }
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
