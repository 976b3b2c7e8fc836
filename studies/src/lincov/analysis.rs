//! LinCov of each filter along the scenario's nominal trajectory (`entrynav::sim::lincov_entry`,
//! Maybeck vol. 1 ch. 6; Geller 2006), timed, and the mean error's share of its NEES.

use crate::error::{StudyError, StudyResult};
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::Scenario;
use entrynav::sim::lincov::{EntryLinCov, EntryLinCovError, LinCovOptions, entry_lincov_with};
use entrynav::sim::monte_carlo::report::FilterReport;
use std::time::Instant;

/// One analysed filter with its wall time.
pub struct Analysed {
    /// The prediction.
    pub lincov: EntryLinCov,
    /// Its wall time \[s\].
    pub seconds: f64,
}

/// LinCov of every filter of `kinds` on `scenario` (named `label` in errors). A failed nominal
/// truth is a failure; a filter or scenario LinCov cannot analyse is refused.
pub fn analyse(
    scenario: &Scenario,
    kinds: &[FilterKind],
    label: &str,
    options: LinCovOptions,
) -> StudyResult<Vec<Analysed>> {
    let mut analysed = Vec::with_capacity(kinds.len());
    for &kind in kinds {
        let started = Instant::now();
        let lincov = entry_lincov_with(scenario, kind, options).map_err(|e| {
            let text = format!("LinCov of '{}' on '{label}': {e}", kind.name());
            match e {
                EntryLinCovError::Truth(_) => StudyError::Failed(text),
                _ => StudyError::Refused(text),
            }
        })?;
        let seconds = started.elapsed().as_secs_f64();
        analysed.push(Analysed { lincov, seconds });
    }
    Ok(analysed)
}

/// The filters of `list` (comma-separated) for LinCov: at least one.
pub fn parse_filters(list: &str, scenario: &Scenario) -> StudyResult<Vec<FilterKind>> {
    let kinds = crate::filters::fitting_filters("filters", list, &scenario.onboard)?;
    if kinds.is_empty() {
        return Err(StudyError::Refused(format!(
            "--filter '{list}': name at least one filter (LinCov supports: ekf, ukf, ci, dcifaif)"
        )));
    }
    Ok(kinds)
}

/// The NEES/dof share of a mean error, time average and final
/// ([`EntryLinCovEpoch::nees_of_mean`](entrynav::sim::lincov::EntryLinCovEpoch::nees_of_mean)):
/// LinCov's own with `mc = None`, else the Monte Carlo's mean error per epoch scored in LinCov's
/// onboard covariance, over the epochs both have. A share the Monte Carlo has and LinCov does not
/// is a second-order mean error (docs/results.md, CI on orbiters-3).
pub fn mean_error_nees(l: &EntryLinCov, mc: Option<&FilterReport>) -> (f64, f64) {
    let mut vals = Vec::with_capacity(l.epochs.len());
    let mut j = 0;
    for e in &l.epochs {
        let v = match mc {
            None => e.nees_of_mean(&e.mean_error),
            Some(f) => {
                let s = &f.series;
                while j < s.times_s.len() && s.times_s[j] < e.t - 1e-6 {
                    j += 1;
                }
                if j == s.times_s.len() || (s.times_s[j] - e.t).abs() > 1e-6 {
                    continue;
                }
                let m: Vec<f64> = s.bias[j].iter().map(|v| v.unwrap_or(f64::NAN)).collect();
                e.nees_of_mean(&m)
            }
        };
        vals.push(v.unwrap_or(f64::NAN));
    }
    let avg = vals.iter().sum::<f64>() / vals.len() as f64;
    let last = match (mc, l.epochs.last()) {
        (None, _) => vals.last().copied(),
        (Some(f), Some(e)) => f
            .series
            .times_s
            .last()
            .filter(|t| (*t - e.t).abs() <= 1e-6)
            .and(vals.last().copied()),
        _ => None,
    };
    (avg, last.unwrap_or(f64::NAN))
}
