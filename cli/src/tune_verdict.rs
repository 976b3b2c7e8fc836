//! Whether a tuning may be written: `entrynav tune` checks its own answer on the fresh validation
//! runs, filter by filter, and refuses (unless `--force`) a file that makes any filter worse than
//! the input — fewer epochs inside the NEES band, or a higher time-averaged or final position
//! RMSE, each by more than [`TOLERANCE`] — saying which filter and which figure. The written
//! numbers are compacted to 6 significant digits.

use entrynav::sim::report::FilterReport;

/// Relative change tolerated before a figure counts as worse (10 %).
pub const TOLERANCE: f64 = 0.10;

/// Every figure on which a filter is worse after the tuning than before (fresh runs).
pub fn worse_figures(before: &[FilterReport], after: &[FilterReport]) -> Vec<String> {
    let mut out = Vec::new();
    for (b, a) in before.iter().zip(after) {
        let band = |r: &FilterReport| r.consistency.nees_in_bounds_frac;
        if let (Some(x), Some(y)) = (band(b), band(a))
            && y < (1.0 - TOLERANCE) * x
        {
            out.push(format!(
                "{}: epochs inside the NEES band {:.1} % -> {:.1} %",
                a.name,
                100.0 * x,
                100.0 * y
            ));
        }
        for (label, pick) in [
            (
                "time-averaged position RMSE",
                rmse_avg as fn(&FilterReport) -> Option<f64>,
            ),
            ("final position RMSE", rmse_final),
        ] {
            if let (Some(x), Some(y)) = (pick(b), pick(a))
                && y > (1.0 + TOLERANCE) * x
            {
                out.push(format!("{}: {label} {x:.4} m -> {y:.4} m", a.name));
            }
        }
    }
    out
}

/// Time-averaged position RMSE \[m\].
pub fn rmse_avg(r: &FilterReport) -> Option<f64> {
    r.rmse_time_avg.get("pos_m").copied().flatten()
}

/// Final position RMSE \[m\].
pub fn rmse_final(r: &FilterReport) -> Option<f64> {
    r.rmse_final.get("pos_m").copied().flatten()
}

/// `text` (a scenario's TOML) with every number in a value position (after `= ` or alone on an
/// array line) that has more than six significant digits or reads as a long run of zeros written
/// with at most six: `0.000000000000020556425029701622` becomes `2.05564e-14`. Comments,
/// strings and integers are left alone.
pub fn compact_numbers(text: &str) -> String {
    text.lines()
        .map(|line| {
            let trimmed = line.trim_start();
            if trimmed.starts_with('#') {
                return line.to_string();
            }
            // The number token: the whole element of an array line, or after `key = `.
            let (head, tail) = match line.split_once(" = ") {
                Some((k, v)) => (format!("{k} = "), v.to_string()),
                None => (String::new(), line.to_string()),
            };
            let indent_len = tail.len() - tail.trim_start().len();
            let (indent, body) = tail.split_at(indent_len);
            let (token, rest) = match body.strip_suffix(',') {
                Some(t) => (t, ","),
                None => (body, ""),
            };
            match compact(token) {
                Some(c) => format!("{head}{indent}{c}{rest}"),
                None => line.to_string(),
            }
        })
        .collect::<Vec<_>>()
        .join("\n")
        + if text.ends_with('\n') { "\n" } else { "" }
}

/// A float token rewritten to at most 6 significant digits (exponent form below 1e-4 and from
/// 1e6), or `None` when it is not a float or needs no change.
fn compact(token: &str) -> Option<String> {
    if !token.contains('.') && !token.contains('e') && !token.contains('E') {
        return None;
    }
    let x: f64 = token.parse().ok()?;
    if !x.is_finite() || x == 0.0 {
        return None;
    }
    let sci = format!("{x:.5e}");
    let (mantissa, exp) = sci.split_once('e')?;
    let mantissa = mantissa.trim_end_matches('0').trim_end_matches('.');
    let exp: i32 = exp.parse().ok()?;
    let out = if !(-4..6).contains(&exp) {
        format!("{mantissa}e{exp}")
    } else {
        let v: f64 = format!("{mantissa}e{exp}").parse().ok()?;
        let s = format!("{v}");
        if s.contains('.') { s } else { format!("{s}.0") }
    };
    (out != token).then_some(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_are_compacted_to_six_significant_digits() {
        let text = "# q = 0.000000000000020556425029701622\nq_diag = [\n    0.000000000000020556425029701622,\n    100.0,\n    1234567.891,\n]\nname = \"a.b\"\nx = 0.25\nn = 3\n";
        let out = compact_numbers(text);
        assert_eq!(
            out,
            "# q = 0.000000000000020556425029701622\nq_diag = [\n    2.05564e-14,\n    100.0,\n    1.23457e6,\n]\nname = \"a.b\"\nx = 0.25\nn = 3\n"
        );
        // Every rewritten number parses back within 6 significant digits.
        let v: f64 = "2.05564e-14".parse().unwrap();
        assert!((v / 2.0556425029701622e-14 - 1.0).abs() < 5e-6);
    }
}
