//! The summary tables of a trade report: consistency verdicts (ANEES and ANIS against their
//! χ² bands), RMSE beside the PCRLB, failures and timing.

use super::html::{Cell, num, table};
use entrynav::sim::{FilterReport, TradeReport};

/// Where an average normalised error lies against its two-sided 95 % band.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Verdict {
    /// Inside the band.
    Consistent,
    /// Above: the filter's covariance is too small for its errors.
    Optimistic,
    /// Below: the covariance is larger than the errors.
    Pessimistic,
    /// No value.
    Unknown,
}

impl Verdict {
    /// The verdict of `value` against `band`.
    pub fn of(value: Option<f64>, band: [f64; 2]) -> Verdict {
        match value {
            Some(v) if v > band[1] => Verdict::Optimistic,
            Some(v) if v < band[0] => Verdict::Pessimistic,
            Some(v) if v.is_finite() => Verdict::Consistent,
            _ => Verdict::Unknown,
        }
    }

    /// A table cell showing the verdict.
    pub fn cell(self) -> Cell {
        let (text, class) = match self {
            Verdict::Consistent => ("consistent", "ok"),
            Verdict::Optimistic => ("optimistic (errors exceed σ)", "bad"),
            Verdict::Pessimistic => ("pessimistic (σ exceeds errors)", "warn"),
            Verdict::Unknown => ("–", ""),
        };
        Cell {
            text: text.into(),
            class,
        }
    }
}

fn pct(v: Option<f64>) -> String {
    v.map_or("–".into(), |v| format!("{:.0} %", 100.0 * v))
}

fn band(b: [f64; 2]) -> String {
    format!("[{}, {}]", num(Some(b[0])), num(Some(b[1])))
}

/// Per filter: ANEES (all states, kinematic) and ANIS against their bands, with verdicts.
pub fn consistency_table(report: &TradeReport) -> String {
    let rows: Vec<Vec<Cell>> = report
        .filters
        .iter()
        .map(|f| {
            let c = &f.consistency;
            vec![
                Cell::text(f.name.clone()),
                Cell::num(num(c.anees)),
                Cell::num(c.nees_dof.to_string()),
                Cell::num(band(c.nees_bounds_95)),
                Cell::num(pct(c.nees_in_bounds_frac)),
                Verdict::of(c.anees, c.nees_bounds_95).cell(),
                Cell::num(num(c.anees_kinematic)),
                Verdict::of(c.anees_kinematic, c.nees_kinematic_bounds_95).cell(),
                Cell::num(num(c.anis)),
                Cell::num(band(c.nis_bounds_95)),
                Verdict::of(c.anis, c.nis_bounds_95).cell(),
            ]
        })
        .collect();
    table(
        &[
            "filter",
            "ANEES",
            "dof",
            "χ² 95 % band",
            "epochs in band",
            "NEES verdict",
            "ANEES kinematic (dof 6)",
            "kinematic verdict",
            "ANIS",
            "NIS band",
            "NIS verdict",
        ],
        &rows,
    )
}

fn get(m: &std::collections::BTreeMap<String, Option<f64>>, k: &str) -> Option<f64> {
    m.get(k).copied().flatten()
}

/// Per filter: position and velocity RMSE (time average, final) beside the PCRLB and the
/// efficiency RMSE/PCRLB.
pub fn rmse_table(report: &TradeReport) -> String {
    let bound = report.pcrlb.as_ref().filter(|b| b.available);
    let mut rows: Vec<Vec<Cell>> = Vec::new();
    let metric = |k: &str, f: &FilterReport| {
        vec![
            Cell::num(num(get(&f.rmse_time_avg, k))),
            Cell::num(num(get(&f.rmse_final, k))),
            Cell::num(num(get(&f.efficiency_time_avg, k))),
            Cell::num(num(get(&f.efficiency_final, k))),
        ]
    };
    for f in &report.filters {
        let mut row = vec![Cell::text(f.name.clone())];
        row.extend(metric("pos_m", f));
        row.extend(metric("vel_mps", f));
        row.push(Cell::num(format!("{} / {}", f.failed, f.diverged)));
        row.push(Cell::num(format!("{:.2}", f.us_per_step)));
        rows.push(row);
    }
    if let Some(b) = bound {
        let mut row = vec![Cell::text("PCRLB (lower bound)")];
        for k in ["pos_m", "vel_mps"] {
            row.push(Cell::num(num(get(&b.time_avg, k))));
            row.push(Cell::num(num(get(&b.final_, k))));
            row.push(Cell::num("1"));
            row.push(Cell::num("1"));
        }
        row.extend([Cell::num(""), Cell::num("")]);
        rows.push(row);
    }
    table(
        &[
            "filter",
            "pos RMSE avg (m)",
            "pos RMSE final (m)",
            "pos RMSE/PCRLB avg",
            "pos RMSE/PCRLB final",
            "vel RMSE avg (m/s)",
            "vel RMSE final (m/s)",
            "vel RMSE/PCRLB avg",
            "vel RMSE/PCRLB final",
            "failed / diverged",
            "µs per step",
        ],
        &rows,
    )
}

/// Per filter and state: time-averaged and final RMSE and the fraction of samples inside ±3σ.
pub fn state_table(report: &TradeReport, f: &FilterReport) -> String {
    let rows: Vec<Vec<Cell>> = report
        .states
        .iter()
        .map(|s| {
            let (q, u) = crate::plot::labels::quantity(s);
            vec![
                Cell::text(format!("{q} ({u})")),
                Cell::num(num(get(&f.rmse_time_avg, s))),
                Cell::num(num(get(&f.rmse_final, s))),
                Cell::num(num(get(&f.final_error_mean, s))),
                Cell::num(pct(get(&f.within_3sigma_frac, s))),
            ]
        })
        .collect();
    table(
        &[
            "state",
            "RMSE avg",
            "RMSE final",
            "mean error final",
            "inside ±3σ",
        ],
        &rows,
    )
}

/// Per filter: the deployment 3σ ellipse.
pub fn ellipse_table(report: &TradeReport) -> String {
    let rows: Vec<Vec<Cell>> = report
        .filters
        .iter()
        .filter_map(|f| {
            let e = f.ellipse_km.as_ref()?;
            Some(vec![
                Cell::text(f.name.clone()),
                Cell::num(num(Some(1e3 * e.semi_major_km))),
                Cell::num(num(Some(1e3 * e.semi_minor_km))),
                Cell::num(format!("{:.1}", e.orientation_deg)),
                Cell::num(num(Some(1e3 * e.mean_downrange_km))),
                Cell::num(num(Some(1e3 * e.mean_crossrange_km))),
            ])
        })
        .collect();
    table(
        &[
            "filter",
            "3σ semi-major (m)",
            "3σ semi-minor (m)",
            "major axis from downrange (°)",
            "mean downrange (m)",
            "mean crossrange (m)",
        ],
        &rows,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn verdicts_follow_the_band() {
        let b = [0.8, 1.2];
        assert_eq!(Verdict::of(Some(1.0), b), Verdict::Consistent);
        assert_eq!(Verdict::of(Some(3.0), b), Verdict::Optimistic);
        assert_eq!(Verdict::of(Some(0.1), b), Verdict::Pessimistic);
        assert_eq!(Verdict::of(None, b), Verdict::Unknown);
    }
}
