//! Monte Carlo metrics: the accumulator of one filter's runs, folded in run order (what one run
//! records is in [`super::run_record`], the sums in [`super::moments`], the summary,
//! [`FilterAccumulator::report`], in [`super::report`]).
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
use super::gate_stats::GateSums;
use super::moments::{EpochSums, FinalSums};
use super::run_record::{EpochRecord, RunRecord};
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

/// Sums over runs of one filter, folded in run-index order so results do not depend on thread
/// count: per epoch ([`EpochSums`]), at the final epoch ([`FinalSums`]), NEES/NIS
/// ([`ConsistencySums`]), the ±3σ counts per state, and the runs' outcomes.
///
/// Serialisable so that shards of a study can be merged exactly (`trade merge`).
#[derive(Debug, Clone, Default, PartialEq, Serialize, serde::Deserialize)]
pub struct FilterAccumulator {
    /// Epoch times of the longest run \[s\].
    pub(super) times: Vec<f64>,
    /// Sums per epoch.
    pub(super) epochs: Vec<EpochSums>,
    /// NEES and NIS sums.
    pub(super) consistency: ConsistencySums,
    /// Per state, over every (run, epoch) with a truth value: (inside ±3σ, samples).
    pub(super) within_3sigma: Vec<(u64, u64)>,
    /// Sums at the final epoch of the runs that did not fail.
    pub(super) final_sums: FinalSums,
    /// Runs that stopped on a numerical failure.
    pub(super) failed: u64,
    /// Runs whose final NEES exceeds the divergence threshold.
    pub(super) diverged: u64,
    /// The first [`PROBLEMS_KEPT`] failed and diverged runs of each kind.
    pub(super) problems: Vec<RunProblem>,
    /// Wall-clock time in the filter \[ns\] (timing only).
    pub(super) filter_ns: u128,
    /// Filter steps.
    pub(super) steps: u64,
    /// Runs folded in.
    pub(super) runs: u64,
    /// One row per run, in run order (the per-run final-error CSV).
    pub(super) finals: Vec<FinalRow>,
    /// What the innovation gate did (empty without `[filter.gating]`).
    #[serde(default)]
    pub(super) gate: GateSums,
}

/// Whether an epoch's NEES exceeds the divergence threshold.
fn exceeds(e: &EpochRecord) -> bool {
    e.nees
        .is_some_and(|(v, dof)| v > DIVERGENCE_NEES_PER_DOF * dof as f64)
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
        if self.epochs.len() < o.epochs.len() {
            self.epochs.resize(o.epochs.len(), EpochSums::default());
        }
        for (a, b) in self.epochs.iter_mut().zip(&o.epochs) {
            a.merge(b);
        }
        self.consistency.merge(&o.consistency);
        if self.within_3sigma.len() < o.within_3sigma.len() {
            self.within_3sigma.resize(o.within_3sigma.len(), (0, 0));
        }
        for (a, b) in self.within_3sigma.iter_mut().zip(&o.within_3sigma) {
            a.0 += b.0;
            a.1 += b.1;
        }
        self.final_sums.merge(&o.final_sums);
        self.failed += o.failed;
        self.diverged += o.diverged;
        for p in &o.problems {
            self.keep(p.clone());
        }
        self.filter_ns += o.filter_ns;
        self.steps += o.steps;
        self.runs += o.runs;
        self.finals.extend(o.finals.iter().cloned());
        self.gate.merge(&o.gate);
    }

    /// Fold one run in (call in run-index order).
    pub fn add(&mut self, run_index: usize, rec: &RunRecord) {
        self.runs += 1;
        self.filter_ns += rec.filter_ns;
        self.steps += rec.steps as u64;
        if self.times.len() < rec.times.len() {
            self.times = rec.times.clone();
        }
        if self.epochs.len() < rec.epochs.len() {
            self.epochs.resize(rec.epochs.len(), EpochSums::default());
        }
        for (k, (sums, e)) in self.epochs.iter_mut().zip(&rec.epochs).enumerate() {
            sums.add(e);
            self.consistency.add_epoch(k, e);
            if self.within_3sigma.len() < e.err.len() {
                self.within_3sigma.resize(e.err.len(), (0, 0));
            }
            for ((w, err), sigma) in self.within_3sigma.iter_mut().zip(&e.err).zip(&e.sigma) {
                if err.is_finite() {
                    w.1 += 1;
                    if err.abs() <= 3.0 * sigma {
                        w.0 += 1;
                    }
                }
            }
        }
        self.add_outcome(run_index, rec);
        self.gate.add(rec);
        if let (Some(f), Some(last)) = (&rec.final_, rec.epochs.last()) {
            self.final_sums.add(last, f.downrange_crossrange);
        }
    }

    /// The run's row of the final-error file, and its failure or divergence.
    fn add_outcome(&mut self, run_index: usize, rec: &RunRecord) {
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
        } else if let Some(last) = last.filter(|e| exceeds(e)) {
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
    }
}
