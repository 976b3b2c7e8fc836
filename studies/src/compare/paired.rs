//! `trade compare --final-errors A.csv B.csv`: the final RMSE differences from the per-run final
//! errors (`{scenario}_final_errors.csv` of `trade --csv-dir`), paired by run index. No Gaussian
//! assumption: the variances and the A–B covariance of the squared errors are the sample ones, so
//! heavy tails (diverged runs) and the correlation of runs that share a seed are both accounted
//! for. With K runs valid in both, squared errors aᵣ, bᵣ and mean squares Mₐ, M_b, the delta
//! method gives
//!
//! Var(√M_b − √Mₐ) ≈ [Var b / (4 M_b) + Var a / (4 Mₐ) − 2 Cov(a, b) / (4 √(Mₐ M_b))] / K.

use crate::error::{StudyError, StudyResult};
use crate::statistics::{Difference, Estimate};
use std::collections::BTreeMap;

/// Final errors of one filter: per column (state, `pos_m`, `vel_mps`), run → error.
type Columns = BTreeMap<String, BTreeMap<u64, f64>>;

/// One final-errors CSV: per filter, its columns.
pub struct FinalErrors {
    filters: BTreeMap<String, Columns>,
}

impl FinalErrors {
    /// Parse the text of a `{scenario}_final_errors.csv` written by `trade --csv-dir`; what is
    /// wrong (and where) is refused without naming the file (the caller adds it). Failed runs
    /// (numerical stops) are left out, as in the summary's final RMSE.
    pub fn parse(text: &str) -> StudyResult<FinalErrors> {
        let usage = |m: String| StudyError::Refused(m);
        let mut records = csv::ReaderBuilder::new()
            .has_headers(false)
            .flexible(true)
            .from_reader(text.as_bytes())
            .into_records();
        let header = records.next().and_then(Result::ok).unwrap_or_default();
        if header.len() < 4 || header.iter().take(3).ne(["run", "filter", "status"]) {
            return Err(usage(
                "not a final-errors CSV (header run,filter,status,…) from `trade --csv-dir`".into(),
            ));
        }
        let names: Vec<String> = header
            .iter()
            .skip(3)
            .map(|h| h.strip_prefix("err_").unwrap_or(h).to_string())
            .collect();
        let mut filters: BTreeMap<String, Columns> = BTreeMap::new();
        for (i, record) in records.enumerate() {
            let line = record
                .as_ref()
                .ok()
                .and_then(|r| r.position())
                .map_or(i as u64 + 2, |p| p.line());
            let bad = || usage(format!("line {line}: malformed row"));
            let cells = record.map_err(|_| bad())?;
            if cells.len() != header.len() {
                return Err(bad());
            }
            let run: u64 = cells[0].parse().map_err(|_| bad())?;
            if &cells[2] == "failed" {
                continue;
            }
            let columns = filters.entry(cells[1].to_string()).or_default();
            for (name, cell) in names.iter().zip(cells.iter().skip(3)) {
                if name == "nees" || cell.is_empty() {
                    continue;
                }
                let v: f64 = cell.parse().map_err(|_| bad())?;
                if v.is_finite() {
                    columns.entry(name.clone()).or_default().insert(run, v);
                }
            }
        }
        Ok(FinalErrors { filters })
    }
}

/// A paired final-RMSE comparison of one column: the two RMSEs over the K shared runs, B − A and
/// its interval.
pub struct Paired {
    /// State, `pos_m` or `vel_mps`.
    pub state: String,
    /// Runs valid in both.
    pub runs: u64,
    /// A's RMSE over those runs (its own standard error).
    pub a: Estimate,
    /// B's RMSE over those runs.
    pub b: Estimate,
    /// B − A, with the paired standard error.
    pub difference: Difference,
}

/// The paired comparisons of `filter`, one per column in both files (empty if the filter is
/// missing from either).
pub fn compare_filter(a: &FinalErrors, b: &FinalErrors, filter: &str) -> Vec<Paired> {
    let (Some(ca), Some(cb)) = (a.filters.get(filter), b.filters.get(filter)) else {
        return Vec::new();
    };
    ca.iter()
        .filter_map(|(state, ra)| {
            let rb = cb.get(state)?;
            let pairs: Vec<(f64, f64)> = ra
                .iter()
                .filter_map(|(run, ea)| rb.get(run).map(|eb| (ea * ea, eb * eb)))
                .collect();
            paired(state, &pairs)
        })
        .collect()
}

/// The paired comparison of squared errors `pairs` = (aᵣ, bᵣ); `None` below 2 runs.
fn paired(state: &str, pairs: &[(f64, f64)]) -> Option<Paired> {
    let k = pairs.len();
    if k < 2 {
        return None;
    }
    let n = k as f64;
    let ma = pairs.iter().map(|p| p.0).sum::<f64>() / n;
    let mb = pairs.iter().map(|p| p.1).sum::<f64>() / n;
    let (mut vaa, mut vbb, mut vab) = (0.0, 0.0, 0.0);
    for (x, y) in pairs {
        vaa += (x - ma) * (x - ma);
        vbb += (y - mb) * (y - mb);
        vab += (x - ma) * (y - mb);
    }
    let (vaa, vbb, vab) = (vaa / (n - 1.0), vbb / (n - 1.0), vab / (n - 1.0));
    let (ra, rb) = (ma.sqrt(), mb.sqrt());
    let se_of = |var: f64, m: f64| {
        if m > 0.0 {
            (var / (4.0 * m * n)).sqrt()
        } else {
            0.0
        }
    };
    let var_diff = match (ma > 0.0, mb > 0.0) {
        (true, true) => (vbb / (4.0 * mb) + vaa / (4.0 * ma) - 2.0 * vab / (4.0 * ra * rb)) / n,
        _ => se_of(vaa, ma).powi(2) + se_of(vbb, mb).powi(2),
    };
    let se = var_diff.max(0.0).sqrt();
    Some(Paired {
        state: state.to_string(),
        runs: k as u64,
        a: Estimate {
            value: ra,
            se: se_of(vaa, ma),
        },
        b: Estimate {
            value: rb,
            se: se_of(vbb, mb),
        },
        difference: Difference::with_se(ra, rb, se),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> StudyResult<FinalErrors> {
        FinalErrors::parse(text)
    }

    #[test]
    fn a_quoted_filter_name_with_a_comma_reads_back_whole() {
        // A name with a comma is quoted by the CSV writer; splitting lines at commas would see a
        // row one cell too long and refuse the file.
        let text = "run,filter,status,err_r_m,pos_m,vel_mps,nees\n\
                    0,\"ekf, tuned\",ok,1.5,2,0.5,6\n\
                    1,\"ekf, tuned\",failed,,,,\n\
                    2,\"ekf, tuned\",diverged,-3,4,1,900\n";
        let f = parse(text).unwrap();
        let columns = &f.filters["ekf, tuned"];
        assert_eq!(columns["r_m"], BTreeMap::from([(0, 1.5), (2, -3.0)]));
        assert_eq!(columns["pos_m"], BTreeMap::from([(0, 2.0), (2, 4.0)]));
        assert!(!columns.contains_key("nees"));
    }

    #[test]
    fn a_short_row_or_a_foreign_header_is_refused_naming_the_line() {
        let short = "run,filter,status,err_r_m\n0,ekf,ok,1\n1,ekf,ok\n";
        let e = parse(short).err().unwrap().to_string();
        assert_eq!(e, "line 3: malformed row");
        let e = parse("t_s,rmse_r_m\n0,1\n").err().unwrap().to_string();
        assert!(e.contains("not a final-errors CSV"), "{e}");
    }

    #[test]
    fn identical_runs_differ_by_exactly_zero_with_a_zero_width_interval() {
        let pairs: Vec<(f64, f64)> = [1.0, 4.0, 0.25, 9.0].iter().map(|&x| (x, x)).collect();
        let p = paired("r_m", &pairs).unwrap();
        assert_eq!(p.difference.diff, 0.0);
        assert!(p.difference.se.abs() < 1e-12);
        assert!(!p.difference.significant);
    }

    #[test]
    fn a_consistent_small_improvement_on_the_same_runs_is_significant() {
        // B's error is 95 % of A's in every run: invisible to independent intervals over 40 runs,
        // certain when paired.
        let pairs: Vec<(f64, f64)> = (1..=40)
            .map(|r| {
                let e = (r as f64 * 0.37).sin() * 3.0 + 0.1;
                (e * e, (0.95 * e) * (0.95 * e))
            })
            .collect();
        let p = paired("pos_m", &pairs).unwrap();
        assert!(p.difference.diff < 0.0 && p.difference.significant);
        let independent = Difference::of(p.a, p.b);
        assert!(!independent.significant);
        assert!((p.difference.rel.unwrap() + 0.05).abs() < 1e-12);
    }
}
