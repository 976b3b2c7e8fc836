//! `entrynav tune` as a study: the process-noise diagonal (and optionally the assumed measurement
//! noise) that makes each of a scenario's filters consistent, filter by filter, validated on
//! fresh runs with the file as written, and the input scenario's own text with one
//! `[filter.tuned.<name>]` table per filter ([`tuned_file`](crate::tune::tuned_file)).

use crate::error::{StudyError, StudyResult};
use crate::progress::Progress;
use crate::scenario::input::ScenarioInput;
use crate::threads::with_threads;
use crate::tune::comment::{CommentContext, comment_lines};
use crate::tune::filter::{TunedFilter, tune_filter};
use crate::tune::options::TuneStudyOptions;
use crate::tune::tuned_file::{Retune, edit};
use crate::tune::verdict::{still_inconsistent, worse_figures};
use entrynav::scenario::ScenarioConfig;
use entrynav::sim::monte_carlo::report::FilterReport;
use entrynav::sim::monte_carlo::tuning::TuningRuns;
use std::path::Path;
use std::time::Instant;

/// What a tuning study found.
#[derive(Debug, Clone)]
pub struct TuneStudy {
    /// The options it ran with.
    pub options: TuneStudyOptions,
    /// The scenario's own name.
    pub scenario: String,
    /// Seconds from the first recorded run to the last validation.
    pub wall_s: f64,
    /// Each filter's tuning, in the order of `options.filters`.
    pub tuned: Vec<TunedFilter>,
    /// The filters' reports on the tuning runs, before and after.
    pub tuning: (Vec<FilterReport>, Vec<FilterReport>),
    /// The filters' reports on the fresh validation runs, before and after.
    pub fresh: (Vec<FilterReport>, Vec<FilterReport>),
    /// The verdict: every figure on which a filter is worse after the tuning on the fresh runs
    /// ([`worse_figures`]); empty when the tuning may be written.
    pub worse: Vec<String>,
    /// The tuned scenario's text (the input's, comments and layout kept), or `None` when the
    /// verdict refuses it and `force` is not set.
    pub text: Option<String>,
    /// What the written tuning still gets wrong on the fresh runs, one line per filter
    /// ([`still_inconsistent`]): the file is written and the front ends end with a failure.
    pub inconsistent: Vec<String>,
}

impl TuneStudy {
    /// Seed of the fresh validation runs.
    pub fn validation_seed(&self) -> u64 {
        self.options.validation_seed()
    }

    /// The error a front end ends with after writing a tuning that is still inconsistent
    /// (`out`: where it was written); `None` when every filter is consistent or nothing was
    /// written.
    pub fn inconsistency(&self, out: &Path) -> Option<StudyError> {
        (self.text.is_some() && !self.inconsistent.is_empty()).then(|| {
            StudyError::Failed(format!(
                "{} written, but not consistent yet: {}",
                out.display(),
                self.inconsistent.join("; ")
            ))
        })
    }

    /// The error a front end ends with when the verdict refuses the tuned file (a filter worse
    /// on the fresh runs and no `force`); `out` is where it would have been written.
    pub fn refusal(&self, out: &Path) -> Option<StudyError> {
        (self.text.is_none()).then(|| {
            StudyError::Failed(format!(
                "{} not written: the tuning makes a filter worse than the input on the {} fresh \
                 validation runs ({}); --force writes it anyway",
                out.display(),
                self.options.validation_runs,
                self.worse.join("; ")
            ))
        })
    }
}

/// Tune `options.filters` of `input`, reporting each filter's evaluations to `progress`.
pub fn run_tune(
    input: &ScenarioInput,
    options: &TuneStudyOptions,
    progress: Progress<'_>,
) -> StudyResult<TuneStudy> {
    options.validate()?;
    with_threads(options.threads, || tune_scenario(input, options, progress))
}

fn tune_scenario(
    input: &ScenarioInput,
    options: &TuneStudyOptions,
    progress: Progress<'_>,
) -> StudyResult<TuneStudy> {
    let (cfg, sets) = (&input.config, &input.overrides);
    let scenario = input.build()?;
    let kinds = crate::filters::fitting_filters("filters", &options.filters, &scenario.onboard)?;
    let clock = Instant::now();
    let runs = TuningRuns::record(&scenario, options.seed, options.runs)?;
    let fresh = TuningRuns::record(
        &scenario,
        options.validation_seed(),
        options.validation_runs,
    )?;
    let search = options.search();
    let mut tuned = Vec::new();
    for &kind in &kinds {
        let t = tune_filter(&runs, cfg, kind, options.tune_noise, &search, progress)?;
        tuned.push(t);
    }

    // What the written file does: the scenario built from its own text, on both run sets.
    let text = edit(&input.source_text, sets, &retunes(&tuned, None))?;
    let written = check_written(&text, cfg, &tuned)?;
    let tuned_scenario = entrynav_loader::build(written.clone(), &input.dir)?;
    let (old, new) = (&scenario.onboard, &tuned_scenario.onboard);
    let tuning = (runs.evaluate(old, &kinds)?, runs.evaluate(new, &kinds)?);
    let before = fresh.evaluate(old, &kinds)?;
    let after = fresh.evaluate(new, &kinds)?;
    let wall_s = clock.elapsed().as_secs_f64();

    let worse = worse_figures(&before, &after);
    let inconsistent = still_inconsistent(
        &after,
        &entrynav::sim::monte_carlo::state_names::state_names(&tuned_scenario),
    );
    let text = if worse.is_empty() || options.force {
        let context = CommentContext {
            options,
            scenario: input.label(),
            sets,
            objective: search.objective,
            validation_seed: options.validation_seed(),
        };
        let comments = comments(&context, &tuned, (&before, &after), &worse, &inconsistent);
        let text = edit(&input.source_text, sets, &retunes(&tuned, Some(&comments)))?;
        if check_written(&text, cfg, &tuned)? != written {
            return Err(StudyError::Refused(
                "internal error: the commented tuned file differs from the one validated".into(),
            ));
        }
        Some(text)
    } else {
        None
    };
    Ok(TuneStudy {
        options: options.clone(),
        scenario: scenario.config.name.clone(),
        wall_s,
        tuned,
        tuning,
        fresh: (before, after),
        worse,
        text,
        inconsistent,
    })
}

/// The tables to write: every filter whose tuning is not kept, with its comment lines if given
/// (one entry per such filter, in order).
fn retunes<'a>(tuned: &'a [TunedFilter], comments: Option<&'a [Vec<String>]>) -> Vec<Retune<'a>> {
    tuned
        .iter()
        .filter(|t| t.kept.is_none())
        .enumerate()
        .map(|(k, t)| Retune {
            name: t.kind.name(),
            config: &t.retune,
            comment: comments.map_or(&[][..], |c| &c[k]),
        })
        .collect()
}

/// The comment lines of every written table, with a note on each figure the verdict found worse
/// (written anyway with `force`) and a warning naming what is still inconsistent.
fn comments(
    context: &CommentContext<'_>,
    tuned: &[TunedFilter],
    (before, after): (&[FilterReport], &[FilterReport]),
    worse: &[String],
    inconsistent: &[String],
) -> Vec<Vec<String>> {
    tuned
        .iter()
        .zip(before.iter().zip(after))
        .filter(|(t, _)| t.kept.is_none())
        .map(|(t, (b, a))| {
            let mut lines = comment_lines(context, t, b, a);
            let name = format!("{}:", t.kind.name());
            lines.extend(
                worse
                    .iter()
                    .filter(|w| w.starts_with(&name))
                    .map(|w| format!("NOTE: written with --force although worse: {w}")),
            );
            let still = format!("{} is still inconsistent", t.kind.name());
            lines.extend(
                inconsistent
                    .iter()
                    .filter(|w| w.starts_with(&still))
                    .map(|w| format!("WARNING: {w}")),
            );
            lines
        })
        .collect()
}

/// The configuration `text` holds, checked to be `cfg` with exactly the tunings in `tuned`.
fn check_written(
    text: &str,
    cfg: &ScenarioConfig,
    tuned: &[TunedFilter],
) -> StudyResult<ScenarioConfig> {
    let written = ScenarioConfig::from_toml_str(text, "the tuned scenario")?;
    let mut expected = cfg.clone();
    for t in tuned.iter().filter(|t| t.kept.is_none()) {
        expected
            .filter
            .tuned
            .insert(t.kind.name().to_string(), t.retune.clone());
    }
    if written != expected {
        return Err(StudyError::Refused(
            "internal error: the tuned file does not read back as the tuned scenario (the --set \
             overrides or the [filter.tuned] tables were not written as applied)"
                .into(),
        ));
    }
    Ok(written)
}
