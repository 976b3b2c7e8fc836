//! Seeded multi-start global search: argmin's particle swarm followed by a Nelder–Mead polish.
//!
//! Each start `s` runs [`ParticleSwarm`] inside the box `[lower, upper]` with its own random
//! generator (`Xoshiro256PlusPlus` seeded from `seed` and `s`), then polishes the swarm's best
//! point with [`NelderMead`] (dimension-adaptive coefficients), restarted from a fresh simplex
//! while that still improves and with a smaller simplex once it stops (at most
//! [`POLISH_ROUNDS`] rounds). The
//! best of all starts wins (ties go to the lower start index). Starts run in parallel on rayon's
//! pool; since every start owns its generator the answer is the same on any number of threads.
//!
//! The polish is unconstrained: a problem whose variables are periodic (angles) evaluates any
//! real value, and a problem with a feasible region folds its constraint into the cost as a finite
//! graded penalty. Costs that come back NaN or infinite are replaced by [`NON_FINITE_COST`] before
//! argmin sees them.

use crate::error::OptimizerError;
use crate::progress::Progress;
use crate::search_options::{SearchOptions, SearchResult};
use argmin::core::{CostFunction, Error as ArgminError, Executor, State};
use argmin::solver::neldermead::NelderMead;
use argmin::solver::particleswarm::ParticleSwarm;
use rand_xoshiro::Xoshiro256PlusPlus;
use rand_xoshiro::rand_core::SeedableRng;
use rayon::prelude::*;
use std::sync::atomic::{AtomicUsize, Ordering};

/// Most Nelder–Mead rounds per start.
pub const POLISH_ROUNDS: usize = 8;

/// The finite cost that replaces a NaN or infinite one.
pub const NON_FINITE_COST: f64 = 1e30;

/// The seed of start `s`: SplitMix64 of the master seed and the start index.
pub fn start_seed(seed: u64, start: usize) -> u64 {
    let mut z = seed ^ (start as u64).wrapping_mul(0x9E37_79B9_7F4A_7C15);
    z = z.wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

/// Best point, its cost and the swarm's evaluation count of one start.
type StartOutcome = (Vec<f64>, f64, usize);

struct Counted<'a, F> {
    cost: &'a F,
    count: &'a AtomicUsize,
    local: AtomicUsize,
    total: usize,
    progress: Progress<'a>,
}

impl<F: Fn(&[f64]) -> f64> CostFunction for Counted<'_, F> {
    type Param = Vec<f64>;
    type Output = f64;

    fn cost(&self, x: &Self::Param) -> Result<f64, ArgminError> {
        let c = (self.cost)(x);
        self.local.fetch_add(1, Ordering::Relaxed);
        let done = self.count.fetch_add(1, Ordering::Relaxed) + 1;
        if done % 256 == 0 {
            (self.progress)(done.min(self.total), self.total);
        }
        Ok(if c.is_finite() { c } else { NON_FINITE_COST })
    }
}

fn check_box(lower: &[f64], upper: &[f64]) -> Result<(), OptimizerError> {
    if lower.is_empty() || lower.len() != upper.len() {
        return Err(OptimizerError::InvalidInput(format!(
            "search box needs equal, non-empty bounds ({} lower, {} upper)",
            lower.len(),
            upper.len()
        )));
    }
    for (k, (l, u)) in lower.iter().zip(upper).enumerate() {
        if !(l.is_finite() && u.is_finite() && u > l) {
            return Err(OptimizerError::InvalidInput(format!(
                "search box variable {k}: bounds [{l}, {u}] must be finite with upper > lower"
            )));
        }
    }
    Ok(())
}

fn solver_error(what: &'static str, source: ArgminError) -> OptimizerError {
    OptimizerError::Argmin { what, source }
}

/// Minimise `cost` over the box `[lower, upper]` (swarm) and then without bounds (polish).
///
/// `cost` must be cheap to call from several threads; non-finite values are replaced by
/// [`NON_FINITE_COST`]. `progress(done, budget)` is called every 256 evaluations.
pub fn minimize<F>(
    cost: &F,
    lower: &[f64],
    upper: &[f64],
    opts: &SearchOptions,
    progress: Progress<'_>,
) -> Result<SearchResult, OptimizerError>
where
    F: Fn(&[f64]) -> f64 + Sync,
{
    check_box(lower, upper)?;
    if opts.particles < 2 || opts.starts == 0 {
        return Err(OptimizerError::InvalidInput(format!(
            "the swarm needs at least 2 particles and 1 start (got {} particles, {} starts)",
            opts.particles, opts.starts
        )));
    }
    let dim = lower.len();
    let total = opts.budget(dim);
    let count = AtomicUsize::new(0);
    let runs: Vec<Result<StartOutcome, OptimizerError>> = (0..opts.starts)
        .into_par_iter()
        .map(|s| {
            let problem = || Counted {
                cost,
                count: &count,
                local: AtomicUsize::new(0),
                total,
                progress,
            };
            let rng = Xoshiro256PlusPlus::seed_from_u64(start_seed(opts.seed, s));
            let pso = ParticleSwarm::new((lower.to_vec(), upper.to_vec()), opts.particles)
                .with_rng_generator(rng);
            let res = Executor::new(problem(), pso)
                .configure(|st| st.max_iters(opts.iterations as u64))
                .run()
                .map_err(|e| solver_error("particle swarm", e))?;
            let swarm_evals = res
                .problem()
                .problem
                .as_ref()
                .map_or(0, |p| p.local.load(Ordering::Relaxed));
            let state = res.state();
            let best = state.get_best_param().ok_or(OptimizerError::NoPoint {
                what: "particle swarm",
            })?;
            let (x, c) = restarted_polish(
                &problem,
                best.position.clone(),
                state.get_best_cost(),
                lower,
                upper,
                opts,
            )?;
            Ok((x, c, swarm_evals))
        })
        .collect();
    let mut best: Option<(usize, Vec<f64>, f64)> = None;
    let mut start_costs = Vec::with_capacity(runs.len());
    let mut swarm_evaluations = 0;
    for (s, r) in runs.into_iter().enumerate() {
        let (x, c, se) = r?;
        swarm_evaluations += se;
        start_costs.push(c);
        if best.as_ref().is_none_or(|b| c < b.2) {
            best = Some((s, x, c));
        }
    }
    let (best_start, x, c) = best.expect("at least one start");
    let evaluations = count.load(Ordering::Relaxed);
    progress(evaluations, evaluations);
    Ok(SearchResult {
        x,
        cost: c,
        evaluations,
        swarm_evaluations,
        start_costs,
        best_start,
    })
}

/// Restarted Nelder–Mead from `(x, c)`: a fresh simplex lets it leave the ridges where it stalls;
/// the simplex shrinks once a round no longer improves (at most [`POLISH_ROUNDS`] rounds).
fn restarted_polish<'a, F: Fn(&[f64]) -> f64 + 'a>(
    problem: &dyn Fn() -> Counted<'a, F>,
    mut x: Vec<f64>,
    mut c: f64,
    lower: &[f64],
    upper: &[f64],
    opts: &SearchOptions,
) -> Result<(Vec<f64>, f64), OptimizerError> {
    let mut scale = opts.polish_step;
    for _ in 0..POLISH_ROUNDS {
        if opts.polish_iterations == 0 {
            break;
        }
        let (xp, cp) = polish(problem(), &x, lower, upper, scale, opts)?;
        let gain = c - cp;
        if cp < c {
            (x, c) = (xp, cp);
        }
        if gain <= 1e-10 * c.abs().max(1.0) {
            if scale < opts.polish_step / 5.0 {
                break;
            }
            scale /= 3.0;
        }
    }
    Ok((x, c))
}

/// Only the restarted Nelder–Mead polish of [`minimize`], from `x0` (no swarm): for a cost too
/// expensive for a global search, started from the optimum of a cheap proxy. `lower`/`upper` set
/// the simplex size (`polish_step` × the box width); the search itself is unbounded.
pub fn polish_from<F>(
    cost: &F,
    x0: &[f64],
    lower: &[f64],
    upper: &[f64],
    opts: &SearchOptions,
    progress: Progress<'_>,
) -> Result<SearchResult, OptimizerError>
where
    F: Fn(&[f64]) -> f64 + Sync,
{
    check_box(lower, upper)?;
    if x0.len() != lower.len() {
        return Err(OptimizerError::InvalidInput(format!(
            "start point has {} coordinates for a {}-dimensional box",
            x0.len(),
            lower.len()
        )));
    }
    let total = 3 * (x0.len() + 1 + 2 * opts.polish_iterations) * POLISH_ROUNDS;
    let count = AtomicUsize::new(0);
    let problem = || Counted {
        cost,
        count: &count,
        local: AtomicUsize::new(0),
        total,
        progress,
    };
    let c0 = {
        let c = cost(x0);
        if c.is_finite() { c } else { NON_FINITE_COST }
    };
    count.fetch_add(1, Ordering::Relaxed);
    let (x, c) = restarted_polish(&problem, x0.to_vec(), c0, lower, upper, opts)?;
    let evaluations = count.load(Ordering::Relaxed);
    progress(evaluations, evaluations);
    Ok(SearchResult {
        x,
        cost: c,
        evaluations,
        swarm_evaluations: 0,
        start_costs: vec![c],
        best_start: 0,
    })
}

fn polish<F: Fn(&[f64]) -> f64>(
    problem: Counted<'_, F>,
    x0: &[f64],
    lower: &[f64],
    upper: &[f64],
    scale: f64,
    opts: &SearchOptions,
) -> Result<(Vec<f64>, f64), OptimizerError> {
    let mut simplex = vec![x0.to_vec()];
    for k in 0..x0.len() {
        let mut v = x0.to_vec();
        v[k] += scale * (upper[k] - lower[k]);
        simplex.push(v);
    }
    // Dimension-adaptive expansion and shrink coefficients (Gao & Han 2012), better than the
    // standard ones beyond a few variables (argmin caps the contraction at 0.5, the standard value).
    let n = x0.len().max(2) as f64;
    let nm = NelderMead::new(simplex)
        .with_sd_tolerance(1e-13)
        .and_then(|nm| nm.with_alpha(1.0))
        .and_then(|nm| nm.with_gamma(1.0 + 2.0 / n))
        .and_then(|nm| nm.with_sigma(1.0 - 1.0 / n))
        .map_err(|e| solver_error("Nelder-Mead", e))?;
    let res = Executor::new(problem, nm)
        .configure(|st| st.max_iters(opts.polish_iterations as u64))
        .run()
        .map_err(|e| solver_error("Nelder-Mead", e))?;
    let state = res.state();
    let x = state
        .get_best_param()
        .cloned()
        .ok_or(OptimizerError::NoPoint {
            what: "Nelder-Mead",
        })?;
    Ok((x, state.get_best_cost()))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn finds_the_minimum_of_a_shifted_bowl() {
        let f = |x: &[f64]| (x[0] - 0.3).powi(2) + 2.0 * (x[1] + 0.7).powi(2);
        let opts = SearchOptions {
            starts: 2,
            particles: 20,
            iterations: 40,
            ..Default::default()
        };
        let r = minimize(&f, &[-2.0, -2.0], &[2.0, 2.0], &opts, &crate::no_progress).unwrap();
        assert!(
            (r.x[0] - 0.3).abs() < 1e-5 && (r.x[1] + 0.7).abs() < 1e-5,
            "{r:?}"
        );
        assert!(r.evaluations >= 2 * 20 * 41);
        let again = minimize(&f, &[-2.0, -2.0], &[2.0, 2.0], &opts, &crate::no_progress).unwrap();
        assert_eq!(r, again);
    }

    #[test]
    fn polish_from_a_start_reaches_the_nearby_minimum() {
        let f = |x: &[f64]| (x[0] - 0.3).powi(2) + 2.0 * (x[1] + 0.7).powi(2);
        let opts = SearchOptions {
            polish_iterations: 100,
            polish_step: 0.05,
            ..Default::default()
        };
        let r = polish_from(
            &f,
            &[0.0, 0.0],
            &[-2.0, -2.0],
            &[2.0, 2.0],
            &opts,
            &crate::no_progress,
        )
        .unwrap();
        assert!(
            (r.x[0] - 0.3).abs() < 1e-5 && (r.x[1] + 0.7).abs() < 1e-5,
            "{r:?}"
        );
        assert_eq!(r.swarm_evaluations, 0);
        assert!(
            polish_from(
                &f,
                &[0.0],
                &[-2.0, -2.0],
                &[2.0, 2.0],
                &opts,
                &crate::no_progress
            )
            .is_err()
        );
    }

    #[test]
    fn non_finite_costs_never_reach_the_solver() {
        let f = |x: &[f64]| if x[0] > 0.0 { f64::NAN } else { x[0] * x[0] };
        let opts = SearchOptions {
            starts: 1,
            particles: 10,
            iterations: 10,
            ..Default::default()
        };
        let r = minimize(&f, &[-1.0], &[1.0], &opts, &crate::no_progress).unwrap();
        assert!(r.cost.is_finite() && r.cost < 1e-6);
    }

    #[test]
    fn rejects_a_bad_box() {
        let f = |x: &[f64]| x[0];
        let o = SearchOptions::default();
        assert!(minimize(&f, &[1.0], &[0.0], &o, &crate::no_progress).is_err());
        assert!(minimize(&f, &[], &[], &o, &crate::no_progress).is_err());
    }
}
