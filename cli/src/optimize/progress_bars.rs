//! The design studies' progress on standard error: one `indicatif` bar per task of evaluations
//! (the search, a LinCov polish), a spinner with the branch and bound's line (unit `nodes`),
//! nothing with `--quiet`.

use entrynav_studies::StudyResult;
use entrynav_studies::progress::{Progress, Step};
use indicatif::{ProgressBar, ProgressStyle};
use std::sync::{Mutex, MutexGuard};

/// The bar of the current task, keyed by the task (the unit for `nodes`).
type Current = Mutex<Option<(String, ProgressBar)>>;

/// `study` of `input` with `options`, with bars (none with `quiet`), the last one cleared when
/// it returns.
pub fn with_bars<I, O, T>(
    quiet: bool,
    study: fn(&I, &O, Progress<'_>) -> StudyResult<T>,
    input: &I,
    options: &O,
) -> anyhow::Result<T> {
    let current: Current = Mutex::new(None);
    let out = study(input, options, &|s| {
        if !quiet {
            show(&current, s);
        }
    });
    if let Some((_, bar)) = lock(&current).take() {
        bar.finish_and_clear();
    }
    Ok(out?)
}

fn lock(current: &Current) -> MutexGuard<'_, Option<(String, ProgressBar)>> {
    current.lock().unwrap_or_else(|e| e.into_inner())
}

/// Show `s`: a new bar when its task changes.
fn show(current: &Current, s: Step<'_>) {
    let nodes = s.unit == "nodes";
    let key = if nodes { s.unit } else { s.task };
    let mut current = lock(current);
    if current.as_ref().is_none_or(|(k, _)| k != key) {
        if let Some((_, bar)) = current.take() {
            bar.finish_and_clear();
        }
        *current = Some((key.to_string(), new_bar(nodes, s.task)));
    }
    let Some((_, bar)) = current.as_ref() else {
        return;
    };
    if nodes {
        bar.set_message(s.task.to_string());
        bar.tick();
    } else {
        bar.set_length(s.total);
        bar.set_position(s.done);
    }
}

fn new_bar(spinner: bool, label: &str) -> ProgressBar {
    let (bar, template) = match spinner {
        true => (ProgressBar::new_spinner(), "{spinner} {msg} [{elapsed}]"),
        false => (
            ProgressBar::new(1),
            "{spinner} {msg} [{bar:40}] {pos}/{len} evaluations ({eta})",
        ),
    };
    bar.set_style(
        ProgressStyle::with_template(template)
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    bar.set_message(label.to_string());
    bar
}
