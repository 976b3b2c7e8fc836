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

/// A fraction with one decimal: 99.5 % must not read as 100 %.
fn pct1(v: Option<f64>) -> String {
    v.map_or("–".into(), |v| format!("{:.1} %", 100.0 * v))
}

/// The verdict cell of a filter's average `value` against `band`: "diverged" (with the count)
/// when any run diverged or failed, whatever the average says.
fn verdict_cell(f: &FilterReport, value: Option<f64>, band: [f64; 2]) -> Cell {
    let bad = f.diverged + f.failed;
    if bad > 0 {
        return Cell {
            text: format!("diverged in {bad}/{} runs", f.runs),
            class: "bad",
        };
    }
    Verdict::of(value, band).cell()
}

/// Whether a filter has no failed or diverged run and its ANEES has verdict `v`.
fn sound(f: &FilterReport, v: Verdict) -> bool {
    f.failed + f.diverged == 0
        && Verdict::of(f.consistency.anees, f.consistency.nees_bounds_95) == v
}

/// `x` with four significant digits (no exponent): 5.867, 1467, 0.3012.
fn sig4(x: f64) -> String {
    let digits = if x == 0.0 || !x.is_finite() {
        0
    } else {
        (3 - x.abs().log10().floor() as i32).clamp(0, 12) as usize
    };
    format!("{x:.digits$}")
}

fn pos(f: &FilterReport) -> (Option<f64>, Option<f64>) {
    (get(&f.rmse_time_avg, "pos_m"), get(&f.rmse_final, "pos_m"))
}

/// The one-line recommendation at the top of a trade report (and after the CLI's tables): the
/// filter with the lowest time-averaged position RMSE among those with no failed or diverged run
/// and ANEES inside its χ² band; failing that, among those whose σ exceeds their errors
/// (conservative, said so); never an optimistic or diverging one. Then what each other filter is.
pub fn recommendation(report: &TradeReport) -> String {
    let key = |f: &&FilterReport| pos(f).0.unwrap_or(f64::INFINITY);
    let pick = |v: Verdict| {
        report
            .filters
            .iter()
            .filter(|f| sound(f, v))
            .min_by(|a, b| key(a).total_cmp(&key(b)))
    };
    let consistent = pick(Verdict::Consistent);
    let best = consistent.or_else(|| pick(Verdict::Pessimistic));
    let m = |v: Option<f64>| v.map_or("–".to_string(), |x| format!("{} m", sig4(x)));
    let mut parts = Vec::new();
    match best {
        Some(b) => {
            let (avg, fin) = pos(b);
            let c = &b.consistency;
            let among = if report.filters.len() > 1 {
                if consistent.is_some() {
                    " among the consistent filters"
                } else {
                    " among the conservative filters"
                }
            } else {
                ""
            };
            let how = if consistent.is_some() {
                "consistent".to_string()
            } else {
                format!(
                    "no filter is consistent; this one is conservative (σ exceeds its errors, \
                     ANEES/dof {:.2}) and does not diverge",
                    c.anees.unwrap_or(f64::NAN) / c.nees_dof.max(1) as f64
                )
            };
            parts.push(format!(
                "{}: {how}, lowest position RMSE{among} ({} time-averaged, {} final)",
                b.name,
                m(avg),
                m(fin)
            ));
        }
        None => {
            parts.push("none: every filter diverges or is optimistic (errors exceed σ)".to_string())
        }
    }
    for f in &report.filters {
        if best.is_some_and(|b| std::ptr::eq(b, f)) {
            continue;
        }
        let bad = f.failed + f.diverged;
        let text = if bad > 0 {
            // Where a paper predicts the divergence, its section in short (the tables carry the
            // whole sentence).
            let expected = entrynav_studies::trade::expected::expected_divergence(&f.name)
                .filter(|_| f.failed == 0)
                .map_or(String::new(), |_| {
                    " (expected: seed 000 §4.1, [P0] the DCIFAIF paper)".to_string()
                });
            format!("{} diverged in {bad}/{} runs{expected}", f.name, f.runs)
        } else {
            let verdict = match Verdict::of(f.consistency.anees, f.consistency.nees_bounds_95) {
                Verdict::Consistent => "consistent",
                Verdict::Optimistic => "optimistic (errors exceed σ)",
                Verdict::Pessimistic => "pessimistic (σ exceeds errors)",
                Verdict::Unknown => "no NEES",
            };
            match (best.and_then(|b| pos(b).0), pos(f).0) {
                // A lower RMSE from a filter whose σ does not describe its errors is not a reason
                // to fly it: say so where it happens.
                (Some(b), Some(x)) if b > 0.0 && x < b && best.is_some() => format!(
                    "{} {verdict}, {:.2}× the position RMSE (lower, but its σ does not describe \
                     its errors)",
                    f.name,
                    x / b
                ),
                (Some(b), Some(x)) if b > 0.0 => {
                    format!("{} {verdict}, {:.2}× the position RMSE", f.name, x / b)
                }
                _ => format!("{} {verdict}, position RMSE {}", f.name, m(pos(f).0)),
            }
        };
        parts.push(text);
    }
    parts.join("; ")
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
                verdict_cell(f, c.anees, c.nees_bounds_95),
                Cell::num(num(c.anees_kinematic)),
                verdict_cell(f, c.anees_kinematic, c.nees_kinematic_bounds_95),
                Cell::num(num(c.anis)),
                Cell::num(band(c.nis_bounds_95)),
                verdict_cell(f, c.anis, c.nis_bounds_95),
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
            let (q, u) = crate::chart::labels::quantity(s);
            vec![
                Cell::text(format!("{q} ({u})")),
                Cell::num(num(get(&f.rmse_time_avg, s))),
                Cell::num(num(get(&f.rmse_final, s))),
                Cell::num(num(get(&f.final_error_mean, s))),
                Cell::num(pct1(get(&f.within_3sigma_frac, s))),
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
