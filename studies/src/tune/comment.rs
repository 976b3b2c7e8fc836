//! The comment `tune` writes above each `[filter.tuned.<name>]` table: how the filter was tuned
//! (the command that reproduces it, the objective, the factors) and what the tuning does on the
//! fresh validation runs.

use crate::tune::figures::{band, fmt, per_dof, sig3};
use crate::tune::filter::TunedFilter;
use crate::tune::options::TuneStudyOptions;
use crate::tune::search::{TuneObjective, objective};
use crate::tune::tuned_file::six_digits;
use crate::tune::verdict::{rmse_avg, rmse_final};
use entrynav::sim::monte_carlo::report::FilterReport;

/// Where a comment's figures come from: the options, the scenario as the user named it, the
/// objective and the validation runs' seed.
pub(crate) struct CommentContext<'a> {
    /// The study's options.
    pub options: &'a TuneStudyOptions,
    /// The scenario's name or file as given.
    pub scenario: &'a str,
    /// The `--set` overrides the tuning ran with.
    pub sets: &'a [String],
    /// The objective minimised.
    pub objective: TuneObjective,
    /// Seed of the fresh validation runs.
    pub validation_seed: u64,
}

/// The comment above a filter's `[filter.tuned.<name>]` table: how it was tuned and what it does.
pub(crate) fn comment_lines(
    c: &CommentContext<'_>,
    t: &TunedFilter,
    before: &FilterReport,
    after: &FilterReport,
) -> Vec<String> {
    let o = c.options;
    let mut flags = String::new();
    if o.nis_only {
        flags.push_str(" --nis-only");
    }
    if o.tune_noise {
        flags.push_str(" --tune-noise");
    }
    for s in c.sets {
        flags.push_str(&format!(" --set {s}"));
    }
    let factors: Vec<String> = t
        .factors
        .iter()
        .map(|f| format!("{} x {}", f.name, six_digits(f.factor)))
        .collect();
    vec![
        format!(
            "{}: its own tuning, by `entrynav tune --scenario {} --filter {}{flags} --runs {} --seed {}`",
            t.kind.name(),
            c.scenario,
            o.filters,
            o.runs,
            o.seed
        ),
        format!(
            "Nelder-Mead over log10 factors from the previous tuning, {} evaluations, J {} -> {} with",
            t.result.evaluations,
            sig3(objective(&t.result.initial, c.objective)),
            sig3(t.result.cost)
        ),
        format!(
            "  J = {}",
            match c.objective {
                TuneObjective::NeesAndNis =>
                    "ln^2(ANEES/dof) + mean_k ln^2(NEES_k/dof) + ln^2(ANIS/dof) + NIS band shortfall^2 + mean_channels ln^2(NIS/dof) + 25 x (failed or diverged fraction)",
                TuneObjective::NisOnly =>
                    "ln^2(ANIS/dof) + NIS band shortfall^2 + mean_channels ln^2(NIS/dof) + 25 x (failed or diverged fraction)",
            }
        ),
        format!("factors: {}", factors.join(", ")),
        format!(
            "fresh validation, {} runs (seed {}): ANEES/dof {} -> {}, epochs in the NEES band {} -> {}, \
             ANIS/dof {} -> {},",
            o.validation_runs,
            c.validation_seed,
            fmt(per_dof(before)),
            fmt(per_dof(after)),
            band(before),
            band(after),
            fmt(before.consistency.anis_per_dof),
            fmt(after.consistency.anis_per_dof),
        ),
        format!(
            "  position RMSE time-averaged {} -> {} m, final {} -> {} m",
            fmt(rmse_avg(before)),
            fmt(rmse_avg(after)),
            fmt(rmse_final(before)),
            fmt(rmse_final(after)),
        ),
    ]
}
