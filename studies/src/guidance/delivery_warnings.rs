//! What a delivery table must say beside its numbers (issue "Guided entries that deploy every
//! time"): a filter in the loop whose own σ does not describe its error at deployment, and a miss
//! set by navigation rather than by guidance.
//!
//! * **Inconsistent at deployment**: the mean over the deployed runs of the kinematic NEES
//!   eᵀP⁻¹e (6 states) lies outside the two-sided 95 % band of a mean of N χ²(6) values,
//!   χ²(6N)/N (Bar-Shalom, Li & Kirubarajan 2001 §5.4).
//! * **Navigation-limited**: the filter's RMS miss exceeds perfect navigation's by more than
//!   [`NAV_LIMITED_RATIO`]; the line gives the navigation error at deployment beside both misses.
//! * **Outside the box** (every row): deployed runs whose true altitude, speed or dynamic
//!   pressure at deployment broke `guidance.deploy_box`, by limit — a deployment the parachute
//!   cannot take; it still counts as deployed and its miss stays in the statistics.

use entrynav::estimation::chi_square::chi_square_quantile;
use entrynav::sim::guided::delivery::{DeliveryReport, DeliveryRow};

/// RMS miss over perfect navigation's above which a filter's miss is navigation-limited.
pub const NAV_LIMITED_RATIO: f64 = 1.2;

/// The rows that are not filters.
const NOT_FILTERS: [&str; 2] = ["perfect-nav", "unguided"];

/// Every warning of `report`, one line each, filters in row order.
pub fn delivery_warnings(report: &DeliveryReport) -> Vec<String> {
    let perfect = report
        .rows
        .iter()
        .find(|r| r.name == "perfect-nav")
        .and_then(|r| r.rms_miss_m);
    let mut out: Vec<String> = report.rows.iter().filter_map(outside_box).collect();
    for row in report
        .rows
        .iter()
        .filter(|r| !NOT_FILTERS.contains(&r.name.as_str()))
    {
        out.extend(inconsistent(row));
        out.extend(navigation_limited(row, perfect));
    }
    out
}

fn outside_box(row: &DeliveryRow) -> Option<String> {
    let outside = row
        .deployed
        .checked_sub(row.inside_box)
        .filter(|&n| n > 0)?;
    let limits: Vec<String> = row
        .outside_box_by_limit
        .iter()
        .map(|(limit, n)| format!("{n} {limit}"))
        .collect();
    Some(format!(
        "{}: {outside} of {} deployed runs outside the deployment box ({}), counted as deployed \
         and in the miss statistics; {} of {} runs deployed inside it",
        row.name,
        row.deployed,
        limits.join(", "),
        row.inside_box,
        row.deployed + row.failures
    ))
}

fn inconsistent(row: &DeliveryRow) -> Option<String> {
    let (nees, n) = (row.mean_nees_kinematic?, row.deployed);
    if n == 0 {
        return None;
    }
    let dof = 6 * n;
    let lo = chi_square_quantile(0.025, dof) / dof as f64;
    let hi = chi_square_quantile(0.975, dof) / dof as f64;
    let per_dof = nees / 6.0;
    if (lo..=hi).contains(&per_dof) {
        return None;
    }
    let how = if per_dof > hi {
        "optimistic: its σ is far smaller than its error, so guidance trusts a wrong state"
    } else {
        "pessimistic: its σ is larger than its error"
    };
    Some(format!(
        "{} in the loop is inconsistent at deployment: mean kinematic NEES/dof {} (95 % band \
         [{lo:.3}, {hi:.3}] over {n} runs), {how}; navigation error there {} RMS",
        row.name,
        short(per_dof),
        metres(row.rms_nav_position_error_m)
    ))
}

fn navigation_limited(row: &DeliveryRow, perfect: Option<f64>) -> Option<String> {
    let (miss, perfect) = (row.rms_miss_m?, perfect?);
    if perfect <= 0.0 || miss <= NAV_LIMITED_RATIO * perfect {
        return None;
    }
    Some(format!(
        "{}'s miss is navigation-limited: RMS miss {} against {} with perfect navigation \
         ({:.2}×), with a navigation error at deployment of {} RMS",
        row.name,
        metres(Some(miss)),
        metres(Some(perfect)),
        miss / perfect,
        metres(row.rms_nav_position_error_m)
    ))
}

/// "4.14 km", "812 m", "-".
fn metres(v: Option<f64>) -> String {
    match v {
        Some(m) if m >= 1000.0 => format!("{:.2} km", m / 1000.0),
        Some(m) => format!("{m:.0} m"),
        None => "-".into(),
    }
}

/// About four significant digits: 70507, 523.0, 1.193.
fn short(v: f64) -> String {
    match v.abs() {
        a if a >= 1e5 => format!("{v:.3e}"),
        a if a >= 1e3 => format!("{v:.0}"),
        a if a >= 100.0 => format!("{v:.1}"),
        a if a >= 10.0 => format!("{v:.2}"),
        _ => format!("{v:.3}"),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::collections::BTreeMap;

    fn row(name: &str, rms_miss: f64, nav: Option<f64>, nees: Option<f64>) -> DeliveryRow {
        DeliveryRow {
            name: name.into(),
            deployed: 38,
            failures: 0,
            first_failure: None,
            mean_miss_m: None,
            rms_miss_m: Some(rms_miss),
            median_miss_m: None,
            max_miss_m: None,
            mean_downrange_m: None,
            mean_crossrange_m: None,
            ellipse_99: None,
            max_bank_rate_deg_s: None,
            rate_limit_held: true,
            rms_nav_position_error_m: nav,
            mean_nees_kinematic: nees,
            failures_by_cause: BTreeMap::new(),
            inside_box: 38,
            outside_box_by_limit: BTreeMap::new(),
        }
    }

    fn report(rows: Vec<DeliveryRow>) -> DeliveryReport {
        DeliveryReport {
            scenario: "msl-guided".into(),
            algorithm: "apollo".into(),
            runs: 40,
            seed: 1,
            bank_rate_limit_deg_s: 20.0,
            rows,
            per_run: Vec::new(),
        }
    }

    #[test]
    fn an_overconfident_filter_and_a_navigation_limited_miss_are_named() {
        let r = report(vec![
            row("perfect-nav", 5258.6, None, None),
            row("unguided", 55150.7, None, None),
            row("ekf", 8417.5, Some(4144.7), Some(6.0 * 523.0)),
            row("ukf", 5300.0, Some(40.0), Some(6.0)),
        ]);
        let w = delivery_warnings(&r);
        assert_eq!(w.len(), 2, "{w:?}");
        assert!(
            w[0].starts_with(
                "ekf in the loop is inconsistent at deployment: mean kinematic NEES/dof 523"
            ) && w[0].contains("optimistic")
                && w[0].ends_with("navigation error there 4.14 km RMS"),
            "{}",
            w[0]
        );
        assert!(
            w[1].starts_with("ekf's miss is navigation-limited: RMS miss 8.42 km against 5.26 km with perfect navigation (1.60×)"),
            "{}",
            w[1]
        );
    }

    #[test]
    fn deployments_outside_the_box_are_counted_by_limit() {
        let mut pn = row("perfect-nav", 5258.6, None, None);
        pn.inside_box = 35;
        pn.failures = 2;
        pn.outside_box_by_limit = BTreeMap::from([
            ("altitude below the floor".to_string(), 3),
            ("dynamic pressure above the box".to_string(), 2),
        ]);
        let w = delivery_warnings(&report(vec![pn, row("unguided", 55150.7, None, None)]));
        assert_eq!(
            w,
            [
                "perfect-nav: 3 of 38 deployed runs outside the deployment box (3 altitude below \
              the floor, 2 dynamic pressure above the box), counted as deployed and in the miss \
              statistics; 35 of 40 runs deployed inside it"
            ]
        );
    }
}
