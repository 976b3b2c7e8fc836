//! Filter tuning: the process-noise diagonal (and, optionally, the measurement noise the filter
//! assumes) that makes a navigation filter consistent, found by Nelder–Mead (argmin) on
//! log₁₀ scale factors over a Monte Carlo with common random numbers.
//!
//! A filter is consistent when its normalised errors have the χ² means they claim: ANEES/dof = 1
//! (needs the truth) and ANIS/dof = 1 (innovations only: what a flight team has). The objective is
//!
//! ```text
//! J(θ) = ln²(ANEES/dof) + ln²(ANIS/dof)                       averages over the entry
//!      + mean over epochs of ln²(NEES_k/dof)                   the shape over time
//!      + (0.95 − f_NIS)₊²                                      NIS epochs inside the band
//!      + mean over channels of ln²(channel NIS/dof)            per channel
//!      + 25·(fraction of runs that failed or diverged)
//!      + 5·Σ ln²(max(1, position RMSE / the input's))              time-averaged and final
//! ```
//!
//! where NEES_k is epoch k's NEES averaged over the runs and f_NIS the fraction of epochs whose
//! run-averaged NIS lies inside its 95 % χ² band. Averages of 1 can hide an optimistic peak and
//! a conservative tail, and one channel 3000× its predicted variance can hide behind five at 1.
//! The NEES shape is a log-ratio rather than a band fraction because the band of a few tuning
//! runs is wide enough to hide a ±20 % shape that the band of 200 validation runs shows; its
//! sampling floor is about 2/(dof·runs) (0.012 for 7 states and 24 runs). The last term keeps
//! the search from buying consistency with accuracy: a Q that makes the filter consistent by
//! making it 40 % less accurate is not a tuning a user wants (issue 49: the held-out ballistic
//! entry with load-scaled noise was tuned from 198 to 282 m this way, and refused); it costs
//! nothing while the tuning is as accurate as the input, 0.05 for 10 % worse, 0.6 for 40 %.
//! (`--nis-only`: the NEES terms dropped), each factor 10^θ_k bounded to 10^±[`THETA_BOUND`], and a
//! measurement-noise factor also to what the scenario accepts ([`TuningProblem::bounds`]).
//! A filter already consistent within [`TuneOptions::consistent_within`] (5 %) is left as it is:
//! the objective is then flat to within the Monte Carlo noise, and a search would only move Q by
//! decades to fit that noise.
//!
//! The search has two phases. The overall scale of Q is usually off by decades (a paper's Q
//! covers unmodelled errors the simulation does not have), so a scan of one common factor over
//! 10⁻⁶ … 10³ in steps of half a decade comes first; Nelder–Mead then refines every factor from
//! the best common one, with the rest of the budget. The
//! logarithm makes an over-confident filter (ratio 10) and an over-cautious one (ratio 0.1) equally
//! bad; the divergence term dominates any consistency gain (25 × 1 % = 0.25, a ratio of e^0.5 ≈ 1.65).
//! Bar-Shalom, Li & Kirubarajan, *Estimation with Applications to Tracking and Navigation*,
//! §5.4–5.5, give the consistency tests; tuning Q to pass them is their §5.5 "filter tuning".
//!
//! [`TuningProblem`] is what is tuned: the entry filters of a scenario
//! ([`EntryTuning`](crate::tune::entry::EntryTuning)) or, in the tests, a linear Kalman filter
//! whose optimal tuning is known. (Moved here from the geometry crate, `entrynav-optimizer`.)

use crate::error::{StudyError, StudyResult};
use argmin::core::{CostFunction, Error as ArgminError, Executor};
use argmin::solver::neldermead::NelderMead;
use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Largest |θ| (log₁₀ of a factor): factors stay within 10⁻⁶ … 10⁶.
pub const THETA_BOUND: f64 = 6.0;

/// Weight of the fraction of failed or diverged runs in the objective.
pub const DIVERGENCE_PENALTY: f64 = 25.0;

/// Consistency of a filter under one tuning.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Measured {
    /// ANEES over its degrees of freedom (`None` without truth).
    pub anees_per_dof: Option<f64>,
    /// Mean normalised innovation squared per scalar measurement.
    pub anis_per_dof: Option<f64>,
    /// Fraction of runs that failed numerically or diverged.
    pub bad_fraction: f64,
    /// Fraction of epochs whose mean NEES is inside its 95 % band (`None`: not measured).
    pub nees_in_band: Option<f64>,
    /// Mean over epochs of ln²(epoch NEES averaged over runs / dof) (`None`: not measured).
    pub nees_shape: Option<f64>,
    /// Fraction of epochs whose mean NIS is inside its 95 % band (`None`: not measured).
    pub nis_in_band: Option<f64>,
    /// Mean over the measurement channels of ln²(channel NIS/dof) (0: every channel at 1, or
    /// not measured).
    pub channel_spread: f64,
    /// Position RMSE \[m\], time-averaged and final (`None`: not measured).
    pub pos_rmse: Option<[f64; 2]>,
}

/// Weight of a position RMSE above the input's in the objective ([`accuracy_penalty`]).
pub const ACCURACY_WEIGHT: f64 = 5.0;

/// What a tuning's loss of accuracy against the input (`reference`: the input's time-averaged
/// and final position RMSE on the same runs) adds to the objective:
/// [`ACCURACY_WEIGHT`]·Σ ln²(max(1, RMSE/RMSE_input)). Zero when either is not measured.
pub fn accuracy_penalty(m: &Measured, reference: Option<[f64; 2]>) -> f64 {
    let (Some(now), Some(then)) = (m.pos_rmse, reference) else {
        return 0.0;
    };
    now.iter()
        .zip(then)
        .map(|(&a, b)| match a / b {
            r if r.is_finite() && r > 1.0 => r.ln().powi(2),
            r if r.is_nan() => 1e3,
            _ => 0.0,
        })
        .sum::<f64>()
        * ACCURACY_WEIGHT
}

/// The fraction of epochs inside a 95 % band that a consistent filter keeps.
pub const BAND_TARGET: f64 = 0.95;

/// Which consistency the objective asks for.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum TuneObjective {
    /// ANEES/dof and ANIS/dof → 1 (needs the truth: simulation).
    NeesAndNis,
    /// ANIS/dof → 1 only (innovations: what flight data gives).
    NisOnly,
}

/// A filter tuned by log₁₀ factors θ.
pub trait TuningProblem: Sync {
    /// Number of factors.
    fn dim(&self) -> usize;
    /// The range of θ_k the search stays in (clamped, with a penalty outside): ±[`THETA_BOUND`]
    /// unless the factor's own range is narrower (a noise factor the scenario bounds).
    fn bounds(&self, k: usize) -> (f64, f64) {
        let _ = k;
        (-THETA_BOUND, THETA_BOUND)
    }
    /// Consistency of the filter tuned by the factors 10^θ.
    fn evaluate(&self, theta: &[f64]) -> StudyResult<Measured>;
}

/// Options of [`tune`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct TuneOptions {
    /// What to make consistent.
    pub objective: TuneObjective,
    /// Budget of evaluations (each one a Monte Carlo over the tuning runs).
    pub max_evaluations: usize,
    /// Initial simplex edge in log₁₀ units (1: factors of 10).
    pub initial_step: f64,
    /// A filter whose ratios (ANEES/dof and ANIS/dof, or ANIS/dof alone) already lie within
    /// 1 ± this, with no failed or diverged run, is consistent as it is and is not searched: a
    /// search would only fit the tuning runs' noise (default 0.05).
    pub consistent_within: f64,
}

impl Default for TuneOptions {
    fn default() -> Self {
        TuneOptions {
            objective: TuneObjective::NeesAndNis,
            max_evaluations: 150,
            initial_step: 1.0,
            consistent_within: 0.05,
        }
    }
}

/// What [`tune`] found.
#[derive(Debug, Clone, PartialEq)]
pub struct TuneResult {
    /// Best log₁₀ factors.
    pub theta: Vec<f64>,
    /// Their objective.
    pub cost: f64,
    /// Consistency at θ = 0 (the filter as given).
    pub initial: Measured,
    /// Consistency at the best θ.
    pub tuned: Measured,
    /// Evaluations used.
    pub evaluations: usize,
    /// The filter was consistent as given ([`TuneOptions::consistent_within`]): θ = 0, no search.
    pub already_consistent: bool,
}

/// Fewest epochs inside the 95 % band for a filter left as it is (the diagnosis's threshold).
pub const MIN_BAND_FRACTION: f64 = 0.5;

/// Whether `m` is consistent within `1 ± within` for `objective`, with no failed or diverged run
/// and at least [`MIN_BAND_FRACTION`] of the epochs inside each measured band.
pub fn is_consistent(m: &Measured, objective: TuneObjective, within: f64) -> bool {
    let near = |v: Option<f64>| v.is_some_and(|r| (r - 1.0).abs() <= within);
    let in_band = |f: Option<f64>| f.is_none_or(|f| f >= MIN_BAND_FRACTION);
    m.bad_fraction == 0.0
        && near(m.anis_per_dof)
        && in_band(m.nis_in_band)
        && (objective == TuneObjective::NisOnly
            || (near(m.anees_per_dof) && in_band(m.nees_in_band)))
}

/// The objective J of a measured consistency (see the module documentation).
pub fn objective(m: &Measured, objective: TuneObjective) -> f64 {
    let term = |v: Option<f64>| match v {
        Some(r) if r.is_finite() && r > 0.0 => r.ln().powi(2),
        _ => 1e3,
    };
    let shortfall = |f: Option<f64>| f.map_or(0.0, |f| (BAND_TARGET - f).max(0.0).powi(2));
    let nis = term(m.anis_per_dof) + shortfall(m.nis_in_band) + m.channel_spread;
    let consistency = match objective {
        TuneObjective::NeesAndNis => term(m.anees_per_dof) + m.nees_shape.unwrap_or(0.0) + nis,
        TuneObjective::NisOnly => nis,
    };
    consistency + DIVERGENCE_PENALTY * m.bad_fraction
}

struct Cost<'a, P> {
    problem: &'a P,
    objective: TuneObjective,
    /// The input's position RMSE on the tuning runs ([`accuracy_penalty`]).
    reference: Option<[f64; 2]>,
    count: AtomicUsize,
    budget: usize,
    best: Mutex<Option<(f64, Vec<f64>, Measured)>>,
    error: Mutex<Option<StudyError>>,
    progress: &'a (dyn Fn(usize, usize, f64) + Sync),
}

impl<P: TuningProblem> Cost<'_, P> {
    /// The objective at `theta`, counted against the budget. A failed evaluation is kept (the
    /// first one is returned by [`tune`]) and costs as much as a point past the budget.
    fn evaluate(&self, theta: &[f64]) -> f64 {
        let done = self.count.fetch_add(1, Ordering::Relaxed) + 1;
        if done > self.budget {
            // Past the budget every point is worse than the best one found: the simplex stops
            // moving and the executor's iteration cap ends the search.
            return f64::MAX / 4.0;
        }
        let bounds: Vec<(f64, f64)> = (0..theta.len()).map(|k| self.problem.bounds(k)).collect();
        let outside: f64 = theta
            .iter()
            .zip(&bounds)
            .map(|(t, (lo, hi))| (lo - t).max(0.0) + (t - hi).max(0.0))
            .sum();
        let clamped: Vec<f64> = theta
            .iter()
            .zip(&bounds)
            .map(|(t, (lo, hi))| t.clamp(*lo, *hi))
            .collect();
        let m = match self.problem.evaluate(&clamped) {
            Ok(m) => m,
            Err(e) => {
                if let Ok(mut slot) = self.error.lock() {
                    slot.get_or_insert(e);
                }
                return f64::MAX / 4.0;
            }
        };
        let j =
            objective(&m, self.objective) + accuracy_penalty(&m, self.reference) + 10.0 * outside;
        if let Ok(mut best) = self.best.lock()
            && best.as_ref().is_none_or(|b| j < b.0)
        {
            *best = Some((j, clamped, m));
        }
        let best_j = self
            .best
            .lock()
            .ok()
            .and_then(|b| b.as_ref().map(|b| b.0))
            .unwrap_or(j);
        (self.progress)(done, self.budget, best_j);
        j
    }
}

/// The objective as argmin's cost function, borrowing the [`Cost`] so that its best point, count
/// and first error stay with the caller after the run.
struct Borrowed<'c, 'a, P>(&'c Cost<'a, P>);

impl<P: TuningProblem> CostFunction for Borrowed<'_, '_, P> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, theta: &Vec<f64>) -> Result<f64, ArgminError> {
        Ok(self.0.evaluate(theta))
    }
}

/// argmin's failure, in the words the geometry crate used ("solver failure: Nelder-Mead: …");
/// refused (exit code 2), as it was.
fn nelder_mead_error(source: ArgminError) -> StudyError {
    StudyError::Refused(format!("solver failure: Nelder-Mead: {source}"))
}

/// An input the search cannot work with (exit code 2).
fn invalid_input(message: String) -> StudyError {
    StudyError::Refused(format!("invalid input: {message}"))
}

/// Minimise the objective over θ from θ = 0 with Nelder–Mead; `progress(done, budget, best J)`
/// is called after every evaluation.
pub fn tune(
    problem: &impl TuningProblem,
    opts: &TuneOptions,
    progress: &(dyn Fn(usize, usize, f64) + Sync),
) -> StudyResult<TuneResult> {
    let n = problem.dim();
    if n == 0 {
        return Err(invalid_input(
            "nothing to tune: every process-noise entry is zero and measurement noise is not tuned"
                .into(),
        ));
    }
    if opts.max_evaluations < n + 2 {
        return Err(invalid_input(format!(
            "--max-evaluations {} is below the {} a {n}-parameter simplex needs",
            opts.max_evaluations,
            n + 2
        )));
    }
    let initial = problem.evaluate(&vec![0.0; n])?;
    if is_consistent(&initial, opts.objective, opts.consistent_within) {
        progress(1, opts.max_evaluations, objective(&initial, opts.objective));
        return Ok(TuneResult {
            theta: vec![0.0; n],
            cost: objective(&initial, opts.objective),
            initial,
            tuned: initial,
            evaluations: 1,
            already_consistent: true,
        });
    }
    let cost = Cost {
        problem,
        objective: opts.objective,
        reference: initial.pos_rmse,
        count: AtomicUsize::new(0),
        budget: opts.max_evaluations,
        best: Mutex::new(Some((
            objective(&initial, opts.objective),
            vec![0.0; n],
            initial,
        ))),
        error: Mutex::new(None),
        progress,
    };
    // Phase 1: one common factor, half-decade steps (at most a third of the budget).
    let scan: Vec<f64> = (-12..=6)
        .map(|k| k as f64 * 0.5)
        .take((opts.max_evaluations / 3).max(1))
        .collect();
    let mut centre = 0.0;
    let mut best_j = objective(&initial, opts.objective);
    for c in scan {
        let j = cost.evaluate(&vec![c; n]);
        if j < best_j {
            (best_j, centre) = (j, c);
        }
    }
    // Phase 2: Nelder–Mead on every factor from the best common one.
    let mut simplex = vec![vec![centre; n]];
    for k in 0..n {
        let mut v = vec![centre; n];
        v[k] += opts.initial_step;
        simplex.push(v);
    }
    let nm = NelderMead::new(simplex)
        .with_sd_tolerance(1e-6)
        .map_err(nelder_mead_error)?;
    Executor::new(Borrowed(&cost), nm)
        .configure(|st| st.max_iters(opts.max_evaluations as u64))
        .run()
        .map_err(nelder_mead_error)?;
    if let Some(e) = cost.error.into_inner().ok().flatten() {
        return Err(e);
    }
    let evaluations = cost.count.load(Ordering::Relaxed).min(opts.max_evaluations);
    let (j, theta, tuned) = cost
        .best
        .into_inner()
        .ok()
        .flatten()
        .ok_or_else(|| StudyError::Refused("solver failure: tuning found no point".into()))?;
    Ok(TuneResult {
        theta,
        cost: j,
        initial,
        tuned,
        evaluations,
        already_consistent: false,
    })
}
