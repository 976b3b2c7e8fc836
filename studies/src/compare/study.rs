//! `trade compare A.json B.json`: per filter present in both trade summaries, the difference
//! B − A of every RMSE (time-averaged and final, per state, `pos_m`, `vel_mps`), of the ANEES and
//! of the bad-run fraction, with a 95 % Monte Carlo interval and whether it excludes zero; with
//! the per-run final errors of both, paired final-RMSE rows. The standard errors and their
//! assumptions are in [`crate::statistics`]; the notes say which were used.

use crate::compare::filter::compare_filter;
use crate::compare::input::SummaryIn;
use crate::compare::paired::{FinalErrors, compare_filter as paired_filter};
use crate::compare::scenarios::differences;
use crate::compare::types::{Comparison, Row, Source};

fn source(label: &str, s: &SummaryIn) -> Source {
    let p = s.provenance.as_ref();
    Source {
        path: label.to_string(),
        scenario: s.scenario.clone(),
        scenario_fingerprint: p.and_then(|p| p.scenario_fingerprint.clone()),
        overrides: p.map(|p| p.overrides.clone()).unwrap_or_default(),
        seed: s.seed,
        complete: s.complete,
    }
}

fn describe(s: &Source) -> String {
    let fp = s.scenario_fingerprint.as_deref().unwrap_or("none");
    let sets = if s.overrides.is_empty() {
        String::new()
    } else {
        format!(", overrides {}", s.overrides.join(" "))
    };
    format!(
        "{} is scenario `{}` (fingerprint {fp}{sets})",
        s.path, s.scenario
    )
}

/// Compare summary `b` against `a` (of the same scenario or not: what differs is listed), each
/// with its label (the file it was read from); with `paired`, the per-run final errors of A and
/// B with their labels, the paired final-RMSE rows too.
pub fn compare_summaries(
    (la, a): (&str, &SummaryIn),
    (lb, b): (&str, &SummaryIn),
    paired: Option<[(&str, &FinalErrors); 2]>,
) -> Comparison {
    let (sa, sb) = (source(la, a), source(lb, b));
    let (notes, scenario_differences) = scenario_notes(&sa, a, &sb, b);
    let filters = a
        .filters
        .iter()
        .filter_map(|fa| {
            let fb = b.filters.iter().find(|fb| fb.name == fa.name)?;
            Some(compare_filter(fa, fb))
        })
        .collect();
    let missing = |x: &SummaryIn, y: &SummaryIn| {
        x.filters
            .iter()
            .filter(|f| y.filters.iter().all(|g| g.name != f.name))
            .map(|f| f.name.clone())
            .collect()
    };
    let mut cmp = Comparison {
        only_in_a: missing(a, b),
        only_in_b: missing(b, a),
        a: sa,
        b: sb,
        confidence: 0.95,
        notes,
        scenario_differences,
        filters,
    };
    if let Some([(na, fa), (nb, fb)]) = paired {
        add_paired(&mut cmp, fa, fb, &[na, nb]);
    }
    cmp
}

/// The notes on the two summaries (scenarios, seeds, standard errors, partial studies) and what
/// differs between their scenarios.
fn scenario_notes(
    sa: &Source,
    a: &SummaryIn,
    sb: &Source,
    b: &SummaryIn,
) -> (Vec<String>, Vec<String>) {
    let mut notes = Vec::new();
    let same_scenario = match (&sa.scenario_fingerprint, &sb.scenario_fingerprint) {
        (Some(x), Some(y)) => x == y,
        _ => {
            notes.push(
                "a summary has no scenario fingerprint: scenarios checked by name only".into(),
            );
            sa.scenario == sb.scenario
        }
    };
    let mut scenario_differences = Vec::new();
    if !same_scenario {
        let resolved = |s: &SummaryIn| s.provenance.as_ref().and_then(|p| p.scenario.clone());
        match (resolved(a), resolved(b)) {
            (Some(x), Some(y)) => {
                scenario_differences = differences(&x, &y);
                notes.push(format!(
                    "different scenarios: {}; {}; they differ in {} field(s), listed under \
                     scenario_differences",
                    describe(sa),
                    describe(sb),
                    scenario_differences.len()
                ));
            }
            _ => notes.push(format!(
                "different scenarios: {}; {} (a summary from an older entrynav does not carry its \
                 resolved scenario: what differs cannot be listed)",
                describe(sa),
                describe(sb)
            )),
        }
    }
    let shared = a.runs_completed.min(b.runs_completed);
    let same_runs = if a.runs_completed == b.runs_completed {
        "both summaries fly the same runs (paired)".to_string()
    } else {
        format!(
            "the first {shared} runs are the same in both (A has {}, B {})",
            a.runs_completed, b.runs_completed
        )
    };
    notes.push(if sa.seed == sb.seed && same_scenario {
        format!(
            "same scenario and seed {}: {same_runs}; the intervals treat A and B as independent, so they are conservative (a difference called significant is; one not called significant may still be)",
            sa.seed
        )
    } else if sa.seed == sb.seed {
        format!(
            "same seed {} on different scenarios: the runs share random draws and are correlated, which the intervals ignore",
            sa.seed
        )
    } else {
        format!(
            "seeds {} and {}: independent runs, the intervals apply as stated",
            sa.seed, sb.seed
        )
    });
    notes.push(
        "standard errors from the summaries (no per-run errors there), Gaussian large-sample: SE(RMSE) <= RMSE/sqrt(2N) (equality for a zero-mean error; final per-state RMSE use the mean final error: sqrt(2s^4 + 4m^2 s^2)/(2 RMSE sqrt(N))); SE(ANEES) <= ANEES*sqrt(2/(dof N)); diverged runs (heavy tails) make the intervals too narrow".into(),
    );
    for s in [sa, sb].into_iter().filter(|s| !s.complete) {
        notes.push(format!(
            "{} is a partial summary (interrupted study): its completed runs are used",
            s.path
        ));
    }
    (notes, scenario_differences)
}

/// Append the paired final-RMSE rows of every compared filter.
fn add_paired(cmp: &mut Comparison, fa: &FinalErrors, fb: &FinalErrors, files: &[&str]) {
    let mut any = false;
    for f in &mut cmp.filters {
        for p in paired_filter(fa, fb, &f.name) {
            any = true;
            f.rows.push(Row {
                metric: "rmse_final_paired",
                state: p.state,
                a: p.a,
                b: p.b,
                difference: p.difference,
                paired_runs: Some(p.runs),
                band: None,
            });
        }
    }
    cmp.notes.push(if any {
        format!(
            "rmse_final_paired: from the per-run final errors in {}, paired by run index (failed runs left out): sample variances and covariance, no Gaussian assumption; valid for any seeds, and narrow where A and B fly the same runs",
            files.join(" and ")
        )
    } else {
        format!(
            "{} share no filter with the compared ones: no paired rows",
            files.join(" and ")
        )
    });
}
