//! The rows of one filter present in both summaries: B − A of every RMSE (time-averaged and
//! final, headline rows first), of the ANEES (with the χ² band of each) and of the bad-run
//! fraction, each with its Monte Carlo standard errors ([`crate::statistics`]).

use crate::compare::input::{FilterIn, Stats};
use crate::compare::types::{Band, FilterComparison, Row};
use crate::statistics::{
    Difference, Estimate, se_anees, se_fraction, se_rmse_bound, se_rmse_with_mean,
};

/// A named RMSE map of a filter.
type Metric = (&'static str, fn(&FilterIn) -> &Stats);

/// Runs behind a filter's statistics: those that did not stop on a numerical failure.
fn used_runs(f: &FilterIn) -> u64 {
    f.runs.saturating_sub(f.failed).max(1)
}

/// The rows a reader looks at first.
const HEADLINE: [&str; 5] = ["pos_m", "vel_mps", "downrange_m", "crossrange_m", "up_m"];

/// Compare filter `fa` of summary A with `fb` of B.
pub fn compare_filter(fa: &FilterIn, fb: &FilterIn) -> FilterComparison {
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
