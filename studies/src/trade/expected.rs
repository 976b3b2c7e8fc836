//! What the papers say a filter does, so a study can tell an outcome the literature predicts from
//! a defect, and say so once in the same words wherever the outcome is shown (the CLI's tables,
//! `trade --method both`, the HTML report).
//!
//! One case today: covariance intersection without feedback. Each of CI's local filters fuses the
//! IMU with one range beacon, which alone does not observe the entry state, and CI fuses their
//! estimates without feeding the fused one back, so they drift apart from the truth and the fused
//! estimate diverges. The DCIFAIF paper (\[P0\], our copy "seed 000") finds exactly this in its
//! §4.1 ("the navigation accuracy of the CI is the worst in three methods because four subsystems
//! are all unobservable") and motivates its information feedback (§3.4) by it.

use crate::trade::lincov_comparison::ComparedFigure;
use entrynav::sim::FilterReport;

/// The divergence the papers predict for the filter named `filter`, in words that name the
/// source; `None` when a divergence of this filter would be a defect.
pub fn expected_divergence(filter: &str) -> Option<&'static str> {
    match filter {
        "ci" => Some(
            "expected: seed 000 §4.1 ([P0], the DCIFAIF paper): each of CI's local filters \
             (IMU + one beacon) is unobservable alone and CI fuses them without feedback, so its \
             estimate drifts off; DCIFAIF's information feedback ([P0] §3.4) is the remedy",
        ),
        _ => None,
    }
}

/// Whether more than 1 % of `f`'s runs failed or diverged (the share a report warns about).
pub fn mostly_bad(f: &FilterReport) -> bool {
    (f.failed + f.diverged) * 100 > f.runs
}

/// The line a report gives a filter with more than 1 % of its runs failed or diverged, without
/// its indentation: a WARNING when nothing predicts it, the paper's explanation when one does.
/// `None` for a filter at or below 1 %.
pub fn bad_runs_line(f: &FilterReport) -> Option<String> {
    if !mostly_bad(f) {
        return None;
    }
    let bad = f.failed + f.diverged;
    let share = format!(
        "{bad} of {} runs ({:.1}%) failed or diverged",
        f.runs,
        100.0 * bad as f64 / f.runs.max(1) as f64
    );
    Some(match expected_divergence(&f.name) {
        Some(why) if f.failed == 0 => format!("{share}, {why}"),
        _ => format!("WARNING: {share}"),
    })
}

/// Why LinCov and the Monte Carlo of `f` disagree, when some of its compared `rows` lie outside
/// the Monte Carlo's interval (`None` when none does): the Monte Carlo's runs diverged (which a first-order prediction about the nominal cannot show; with the
/// paper's explanation where one applies), or, with no run lost, the dispersed runs left the
/// region where the linear prediction holds.
pub fn lincov_disagreement(f: &FilterReport, rows: &[ComparedFigure]) -> Option<String> {
    let off: Vec<&str> = rows
        .iter()
        .filter(|r| r.disagrees())
        .map(|r| r.figure.as_str())
        .collect();
    if off.is_empty() {
        return None;
    }
    let of = rows.len();
    let head = format!(
        "LinCov and the Monte Carlo disagree beyond the sampling interval on {} of {of} figures ({})",
        off.len(),
        off.join(", ")
    );
    let bad = f.failed + f.diverged;
    if bad == 0 {
        return Some(format!(
            "{head}: the dispersed runs leave the region where the first-order (linear) \
             prediction holds"
        ));
    }
    let lost = format!(
        "{bad} of {} Monte Carlo runs failed or diverged, which a first-order prediction about \
         the nominal cannot show",
        f.runs
    );
    Some(match expected_divergence(&f.name) {
        Some(why) if mostly_bad(f) && f.failed == 0 => format!("{head}: {lost}; {why}"),
        _ => format!("{head}: {lost}"),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn report(name: &str, runs: u64, failed: u64, diverged: u64) -> FilterReport {
        FilterReport {
            name: name.into(),
            runs,
            failed,
            diverged,
            ..Default::default()
        }
    }

    #[test]
    fn a_ci_divergence_is_explained_once_and_anything_else_warned() {
        let ci = report("ci", 200, 0, 200);
        let line = bad_runs_line(&ci).unwrap();
        assert!(
            line.starts_with(
                "200 of 200 runs (100.0%) failed or diverged, expected: seed 000 §4.1"
            ),
            "{line}"
        );
        assert!(!line.contains("WARNING"), "{line}");
        // The same divergence of another filter is a defect: a WARNING, no excuse.
        let ekf = report("ekf", 200, 0, 200);
        assert_eq!(
            bad_runs_line(&ekf).unwrap(),
            "WARNING: 200 of 200 runs (100.0%) failed or diverged"
        );
        // Numerical failures are not what the paper predicts.
        assert!(
            bad_runs_line(&report("ci", 200, 3, 197))
                .unwrap()
                .starts_with("WARNING")
        );
        // 1 % or less: nothing to say beyond the counts.
        assert_eq!(bad_runs_line(&report("ekf", 200, 0, 2)), None);
        // --method both: the disagreement is blamed on the divergence, not on nonlinearity.
        let rows = [
            ComparedFigure {
                figure: "anees_per_dof".into(),
                lincov: 0.7,
                mc: 1.1e7,
                half: 2.0e6,
            },
            ComparedFigure {
                figure: "rmse_time_avg.lift_to_drag".into(),
                lincov: 1.49e-3,
                mc: 1.65e-3,
                half: 5.0e-4,
            },
        ];
        let why = lincov_disagreement(&ci, &rows).unwrap();
        assert!(why.contains("on 1 of 2 figures (anees_per_dof)"), "{why}");
        assert!(
            why.contains("200 of 200 Monte Carlo runs failed or diverged"),
            "{why}"
        );
        assert!(why.contains("expected: seed 000 §4.1"), "{why}");
        assert!(
            !why.contains("first-order (linear) prediction holds"),
            "{why}"
        );
        let ok = report("ekf", 200, 0, 0);
        let why = lincov_disagreement(&ok, &rows).unwrap();
        assert!(
            why.ends_with("first-order (linear) prediction holds"),
            "{why}"
        );
        // No figure outside the interval: nothing to say.
        assert_eq!(lincov_disagreement(&ok, &rows[1..]), None);
    }
}
