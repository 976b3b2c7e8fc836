//! One filter's tuning: the search from the tuning it flies with now, its factors (and whether
//! each sits at its search bound), what the file will hold for it, and whether it is kept as it
//! was (already consistent, or no factor helps enough to be worth writing).

use crate::error::StudyResult;
use crate::progress::{Progress, Step};
use crate::tune::entry::EntryTuning;
use crate::tune::figures::{fmt, sig3};
use crate::tune::search::{TuneOptions, TuneResult, TuningProblem, objective, tune};
use crate::tune::tuned_file::rounded;
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::{FilterRetuneConfig, ScenarioConfig};
use entrynav::sim::monte_carlo::tuning::TuningRuns;
use std::time::Instant;

/// Smallest relative drop of the objective for which a tuning is written: below it the
/// factors only fit the tuning runs' noise.
pub const MIN_GAIN: f64 = 0.10;

/// One tuned factor.
#[derive(Debug, Clone, PartialEq)]
pub struct TunedFactor {
    /// Its name (`q[v_mps]`, `r[range]`).
    pub name: String,
    /// The factor 10^θ found.
    pub factor: f64,
    /// It sits at its search bound.
    pub at_bound: bool,
}

/// One filter's tuning.
#[derive(Debug, Clone)]
pub struct TunedFilter {
    /// The filter.
    pub kind: FilterKind,
    /// Its factors, in the search's order.
    pub factors: Vec<TunedFactor>,
    /// What the search found.
    pub result: TuneResult,
    /// The objective J of the filter as given.
    pub initial_cost: f64,
    /// Seconds the search took.
    pub search_s: f64,
    /// What the file holds for it (six significant digits).
    pub retune: FilterRetuneConfig,
    /// Why its tuning is kept as it was (no table written), if it is.
    pub kept: Option<String>,
}

/// Tune filter `kind` of `cfg` (the configuration the runs were built from) from its current
/// tuning, reporting evaluations to `progress` (task: the filter's name, `best`: the best J).
pub fn tune_filter(
    runs: &TuningRuns,
    cfg: &ScenarioConfig,
    kind: FilterKind,
    tune_noise: bool,
    opts: &TuneOptions,
    progress: Progress<'_>,
) -> StudyResult<TunedFilter> {
    let clock = Instant::now();
    let problem = EntryTuning::new(runs, kind, tune_noise)?;
    let result = tune(&problem, opts, &|done, total, best| {
        progress(Step {
            best: Some(best),
            ..Step::of("evaluations", kind.name(), done as u64, total as u64)
        })
    })?;
    let factors = problem
        .groups()
        .iter()
        .zip(&result.theta)
        .enumerate()
        .map(|(k, (g, t))| {
            let (lo, hi) = problem.bounds(k);
            TunedFactor {
                name: g.name().to_string(),
                factor: 10f64.powf(*t),
                at_bound: *t <= lo + 1e-9 || *t >= hi - 1e-9,
            }
        })
        .collect();
    let retune = rounded(&problem.retune_config(cfg, &result.theta));
    let initial_cost = objective(&result.initial, opts.objective);
    let kept = if result.already_consistent {
        Some(format!(
            "already consistent on the tuning runs (ANEES/dof {}, ANIS/dof {}, within {} %, no \
             failure)",
            fmt(result.initial.anees_per_dof),
            fmt(result.initial.anis_per_dof),
            100.0 * opts.consistent_within
        ))
    } else if result.cost > (1.0 - MIN_GAIN) * initial_cost {
        Some(format!(
            "no factor lowered J by {:.0} % ({} evaluations, J {} -> {}): Q does not limit this \
             filter's consistency (try --tune-noise)",
            100.0 * MIN_GAIN,
            result.evaluations,
            sig3(initial_cost),
            sig3(result.cost)
        ))
    } else {
        None
    };
    Ok(TunedFilter {
        kind,
        factors,
        result,
        initial_cost,
        search_s: clock.elapsed().as_secs_f64(),
        retune,
        kept,
    })
}
