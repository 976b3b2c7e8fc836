//! `entrynav trade compare A.json B.json`: per filter present in both trade summaries, the
//! difference B − A of every RMSE (time-averaged and final, per state, `pos_m`, `vel_mps`), of
//! the ANEES and of the bad-run fraction, with a 95 % Monte Carlo interval and whether it excludes
//! zero. The standard errors and their assumptions are in [`entrynav_studies::statistics`]; the table and
//! the JSON say which were used.

use crate::compare_input::{FilterIn, Stats, SummaryIn, read};
use crate::compare_paired::{self, FinalErrors};
use crate::exit::{check_output_file, is_stdout};
use anyhow::Result;
use entrynav_studies::statistics::{
    Difference, Estimate, se_anees, se_fraction, se_rmse_bound, se_rmse_with_mean,
};
use serde::Serialize;
use std::path::{Path, PathBuf};

/// Arguments of `entrynav trade compare`.
#[derive(clap::Args)]
pub struct CompareArgs {
    /// Trade summary A (written by `trade --json`), the reference.
    pub a: PathBuf,
    /// Trade summary B; differences are B − A.
    pub b: PathBuf,
    /// Write the comparison as JSON (`-`: to standard output, and no table).
    #[arg(long)]
    pub json: Option<PathBuf>,
    /// Accepted for older scripts: different scenarios (a moved beacon, a tuned file) are
    /// compared, and what differs between them is printed.
    #[arg(long, hide = true)]
    pub allow_different_scenarios: bool,
    /// The per-run final errors of A and B (`{scenario}_final_errors.csv` from the same
    /// studies' `--csv-dir`): adds `rmse_final_paired` rows, paired by run index, with sample
    /// variances and covariance instead of the Gaussian approximation.
    #[arg(long, num_args = 2, value_names = ["A.csv", "B.csv"])]
    pub final_errors: Vec<PathBuf>,
}

/// A named RMSE map of a filter.
type Metric = (&'static str, fn(&FilterIn) -> &Stats);

/// One input file as the comparison saw it.
#[derive(Serialize)]
pub struct Source {
    /// The file.
    pub path: String,
    /// Its scenario name.
    pub scenario: String,
    /// Its `provenance.scenario_fingerprint`.
    pub scenario_fingerprint: Option<String>,
    /// Its `--set` overrides.
    pub overrides: Vec<String>,
    /// Its master seed.
    pub seed: u64,
    /// Whether the study finished.
    pub complete: bool,
}

/// One compared quantity of one filter.
#[derive(Serialize)]
pub struct Row {
    /// `rmse_time_avg`, `rmse_final`, `anees`, `anees_kinematic` or `bad_run_fraction`.
    pub metric: &'static str,
    /// State name (`pos_m`, `vel_mps` for the error norms); empty for whole-filter metrics.
    pub state: String,
    /// A and its standard error.
    pub a: Estimate,
    /// B and its standard error.
    pub b: Estimate,
    /// B − A with its 95 % interval.
    #[serde(flatten)]
    pub difference: Difference,
    /// For `rmse_final_paired`: the runs valid in both final-errors files.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub paired_runs: Option<u64>,
    /// For ANEES: the per-epoch 95 % χ² band of A and B and whether each ANEES lies inside.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub band: Option<Band>,
}

/// The χ² consistency band of an ANEES in A and B.
#[derive(Serialize, Clone, Copy)]
pub struct Band {
    /// Degrees of freedom.
    pub dof: usize,
    /// A's band.
    pub a: [f64; 2],
    /// B's band.
    pub b: [f64; 2],
    /// A's ANEES inside its band.
    pub a_inside: bool,
    /// B's ANEES inside its band.
    pub b_inside: bool,
}

/// One filter present in both summaries.
#[derive(Serialize)]
pub struct FilterComparison {
    /// Filter name.
    pub name: String,
    /// Runs used for A's and B's standard errors (runs folded minus numerical failures).
    pub runs: [u64; 2],
    /// Diverged runs in A and B (heavy tails: the intervals are then too narrow).
    pub diverged: [u64; 2],
    /// Compared quantities.
    pub rows: Vec<Row>,
}

/// The whole comparison (also the `--json` output).
#[derive(Serialize)]
pub struct Comparison {
    /// Summary A.
    pub a: Source,
    /// Summary B.
    pub b: Source,
    /// Confidence level of the intervals.
    pub confidence: f64,
    /// How the standard errors were obtained, and what the pairing of runs means.
    pub notes: Vec<String>,
    /// What differs between the two resolved scenarios (`path: A -> B`), when they differ and
    /// both summaries carry them.
    pub scenario_differences: Vec<String>,
    /// Filters in both summaries.
    pub filters: Vec<FilterComparison>,
    /// Filters only in A.
    pub only_in_a: Vec<String>,
    /// Filters only in B.
    pub only_in_b: Vec<String>,
}

/// Run the command.
pub fn run(args: &CompareArgs) -> Result<()> {
    if let Some(p) = &args.json {
        check_output_file(p, "--json")?;
    }
    let a = read(&args.a)?;
    let b = read(&args.b)?;
    let finals = match args.final_errors.as_slice() {
        [fa, fb] => Some((FinalErrors::read(fa)?, FinalErrors::read(fb)?)),
        _ => None,
    };
    let mut cmp = compare(&args.a, &a, &args.b, &b)?;
    if let Some((fa, fb)) = &finals {
        add_paired(&mut cmp, fa, fb, &args.final_errors);
    }
    let to_stdout = args.json.as_deref().is_some_and(is_stdout);
    if !to_stdout {
        crate::compare_table::print(&cmp);
    }
    if let Some(p) = &args.json {
        let text = serde_json::to_string_pretty(&cmp)? + "\n";
        if to_stdout {
            print!("{text}");
        } else {
            entrynav_studies::output::atomic_file::write(p, text)?;
            println!("wrote {}", p.display());
        }
    }
    Ok(())
}

/// Append the paired final-RMSE rows of every compared filter.
fn add_paired(cmp: &mut Comparison, fa: &FinalErrors, fb: &FinalErrors, files: &[PathBuf]) {
    let mut any = false;
    for f in &mut cmp.filters {
        for p in compare_paired::compare_filter(fa, fb, &f.name) {
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
    let names: Vec<String> = files.iter().map(|p| p.display().to_string()).collect();
    cmp.notes.push(if any {
        format!(
            "rmse_final_paired: from the per-run final errors in {}, paired by run index (failed runs left out): sample variances and covariance, no Gaussian assumption; valid for any seeds, and narrow where A and B fly the same runs",
            names.join(" and ")
        )
    } else {
        format!(
            "{} share no filter with the compared ones: no paired rows",
            names.join(" and ")
        )
    });
}

fn source(path: &Path, s: &SummaryIn) -> Source {
    let p = s.provenance.as_ref();
    Source {
        path: path.display().to_string(),
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

/// Compare summary `b` against `a` (of the same scenario or not: what differs is listed).
fn compare(pa: &Path, a: &SummaryIn, pb: &Path, b: &SummaryIn) -> Result<Comparison> {
    let (sa, sb) = (source(pa, a), source(pb, b));
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
                scenario_differences = crate::compare_scenarios::differences(&x, &y);
                notes.push(format!(
                    "different scenarios: {}; {}; they differ in {} field(s), listed under \
                     scenario_differences",
                    describe(&sa),
                    describe(&sb),
                    scenario_differences.len()
                ));
            }
            _ => notes.push(format!(
                "different scenarios: {}; {} (a summary from an older entrynav does not carry its \
                 resolved scenario: what differs cannot be listed)",
                describe(&sa),
                describe(&sb)
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
    for s in [&sa, &sb].into_iter().filter(|s| !s.complete) {
        notes.push(format!(
            "{} is a partial summary (interrupted study): its completed runs are used",
            s.path
        ));
    }
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
    Ok(Comparison {
        only_in_a: missing(a, b),
        only_in_b: missing(b, a),
        a: sa,
        b: sb,
        confidence: 0.95,
        notes,
        scenario_differences,
        filters,
    })
}

/// Runs behind a filter's statistics: those that did not stop on a numerical failure.
fn used_runs(f: &FilterIn) -> u64 {
    f.runs.saturating_sub(f.failed).max(1)
}

/// The rows a reader looks at first.
const HEADLINE: [&str; 5] = ["pos_m", "vel_mps", "downrange_m", "crossrange_m", "up_m"];

fn compare_filter(fa: &FilterIn, fb: &FilterIn) -> FilterComparison {
    let (na, nb) = (used_runs(fa), used_runs(fb));
    let mut rows = Vec::new();
    let pairs: [Metric; 2] = [
        ("rmse_time_avg", |f| &f.rmse_time_avg),
        ("rmse_final", |f| &f.rmse_final),
    ];
    for (metric, pick) in pairs {
        // The headline rows first (position, velocity, local frame), then the states.
        let map = pick(fa);
        let order = HEADLINE
            .iter()
            .filter_map(|h| map.get_key_value(*h))
            .chain(map.iter().filter(|(k, _)| !HEADLINE.contains(&k.as_str())));
        for (state, va) in order {
            let (Some(va), Some(vb)) = (*va, pick(fb).get(state).copied().flatten()) else {
                continue;
            };
            let se = |f: &FilterIn, v: f64, n: u64| {
                let mean = f.final_error_mean.get(state).copied().flatten();
                match mean {
                    Some(m) if metric == "rmse_final" => se_rmse_with_mean(v, m, n),
                    _ => se_rmse_bound(v, n),
                }
            };
            rows.push(row(
                metric,
                state.clone(),
                Estimate {
                    value: va,
                    se: se(fa, va, na),
                },
                Estimate {
                    value: vb,
                    se: se(fb, vb, nb),
                },
                None,
            ));
        }
    }
    let anees = [
        ("anees", fa.anees, fb.anees, fa.nees_dof, fb.nees_dof),
        (
            "anees_kinematic",
            fa.anees_kinematic,
            fb.anees_kinematic,
            6,
            6,
        ),
    ];
    for (metric, a, b, dof_a, dof_b) in anees {
        let (Some(a), Some(b)) = (a, b) else { continue };
        let (band_a, band_b) = if metric == "anees" {
            (fa.nees_bounds_95, fb.nees_bounds_95)
        } else {
            (fa.nees_kinematic_bounds_95, fb.nees_kinematic_bounds_95)
        };
        let band = Band {
            dof: dof_a,
            a: band_a,
            b: band_b,
            a_inside: (band_a[0]..=band_a[1]).contains(&a),
            b_inside: (band_b[0]..=band_b[1]).contains(&b),
        };
        rows.push(row(
            metric,
            String::new(),
            Estimate {
                value: a,
                se: se_anees(a, dof_a as f64, na),
            },
            Estimate {
                value: b,
                se: se_anees(b, dof_b as f64, nb),
            },
            (dof_a == dof_b).then_some(band),
        ));
    }
    let bad = |f: &FilterIn| (f.failed + f.diverged) as f64 / f.runs.max(1) as f64;
    let (pa, pb) = (bad(fa), bad(fb));
    rows.push(row(
        "bad_run_fraction",
        String::new(),
        Estimate {
            value: pa,
            se: se_fraction(pa, fa.runs),
        },
        Estimate {
            value: pb,
            se: se_fraction(pb, fb.runs),
        },
        None,
    ));
    FilterComparison {
        name: fa.name.clone(),
        runs: [na, nb],
        diverged: [fa.diverged, fb.diverged],
        rows,
    }
}

fn row(metric: &'static str, state: String, a: Estimate, b: Estimate, band: Option<Band>) -> Row {
    Row {
        metric,
        state,
        a,
        b,
        difference: Difference::of(a, b),
        paired_runs: None,
        band,
    }
}
