//! Axis ticks a reader can read: "nice" positions (1-2-5 steps on linear axes, decades or
//! 1-2-5 mantissas on logarithmic ones), always at least two inside the range, and labels in
//! engineering notation with as many digits as the tick spacing needs (`30e-6`, `1.5`, `250e3`,
//! never `3.0000000000000004e-5`).

/// Tick positions and their labels for one axis.
#[derive(Debug, Clone, PartialEq)]
pub struct Ticks {
    /// Values inside the axis range, increasing.
    pub values: Vec<f64>,
    /// One label per value.
    pub labels: Vec<String>,
}

impl Ticks {
    /// The label of the tick nearest `v` (the plotting library asks by value).
    pub fn label_of(&self, v: f64) -> String {
        self.values
            .iter()
            .zip(&self.labels)
            .min_by(|a, b| (a.0 - v).abs().total_cmp(&(b.0 - v).abs()))
            .map(|(_, l)| l.clone())
            .unwrap_or_default()
    }
}

/// The 1-2-5 step giving about `target` intervals over `span`.
fn nice_step(span: f64, target: f64) -> f64 {
    let raw = span / target;
    let mag = 10f64.powf(raw.log10().floor());
    let m = raw / mag;
    let nice = if m < 1.5 {
        1.0
    } else if m < 3.5 {
        2.0
    } else if m < 7.5 {
        5.0
    } else {
        10.0
    };
    nice * mag
}

/// Linear ticks over `[lo, hi]` (at least two; about five).
pub fn linear(lo: f64, hi: f64) -> Ticks {
    let (lo, hi) = if hi > lo {
        (lo, hi)
    } else {
        (lo - 0.5, lo + 0.5)
    };
    let mut target = 5.0;
    loop {
        let step = nice_step(hi - lo, target);
        let first = (lo / step).ceil() as i64;
        let last = (hi / step).floor() as i64;
        if last - first >= 1 || target > 40.0 {
            let values: Vec<f64> = (first..=last)
                .map(|i| {
                    let v = i as f64 * step;
                    if v.abs() < step * 1e-9 { 0.0 } else { v }
                })
                .collect();
            let labels = format_axis(&values, step);
            return Ticks { values, labels };
        }
        target *= 2.0;
    }
}

/// Logarithmic ticks over `[lo, hi]`, `0 < lo < hi`: decades when the range spans at least two,
/// else 1-2-5 mantissas, else linear ticks (a range narrower than a factor of two).
pub fn log(lo: f64, hi: f64) -> Ticks {
    if !(lo > 0.0 && hi > lo) {
        return linear(lo, hi);
    }
    let (k0, k1) = (lo.log10().floor() as i32, hi.log10().ceil() as i32);
    for mantissas in [
        &[1.0][..],
        &[1.0, 2.0, 5.0][..],
        &[1.0, 1.5, 2.0, 3.0, 5.0, 7.0],
    ] {
        let values: Vec<f64> = (k0..=k1)
            .flat_map(|k| mantissas.iter().map(move |m| (m * 10f64.powi(k), k)))
            .filter(|(v, _)| *v >= lo * (1.0 - 1e-12) && *v <= hi * (1.0 + 1e-12))
            .map(|(v, _)| v)
            .collect();
        if values.len() >= 2 && (mantissas.len() > 1 || values.len() >= 3) {
            // Too many decades: keep every other one.
            let values = if values.len() > 8 {
                values
                    .iter()
                    .step_by(values.len().div_ceil(6))
                    .copied()
                    .collect()
            } else {
                values
            };
            let labels = values.iter().map(|v| format_single(*v)).collect();
            return Ticks { values, labels };
        }
    }
    linear(lo, hi)
}

/// Engineering exponent (a multiple of 3) of `v`.
fn eng_exponent(v: f64) -> i32 {
    if v == 0.0 || !v.is_finite() {
        return 0;
    }
    (v.abs().log10().floor() as i32).div_euclid(3) * 3
}

/// Mantissa × 10^exp with `decimals` digits; plain when `exp` is 0.
fn render(v: f64, exp: i32, decimals: usize) -> String {
    if v == 0.0 {
        return "0".into();
    }
    let m = v / 10f64.powi(exp);
    let s = format!("{m:.decimals$}");
    let s = if s.starts_with('-') && s[1..].chars().all(|c| c == '0' || c == '.') {
        s[1..].to_string()
    } else {
        s
    };
    if exp == 0 { s } else { format!("{s}e{exp}") }
}

/// Labels of evenly spaced `values` (spacing `step`): one exponent for the axis, chosen from
/// the largest magnitude (plain numbers between 1e-3 and 1e4), digits from the spacing.
pub fn format_axis(values: &[f64], step: f64) -> Vec<String> {
    let big = values.iter().fold(0.0f64, |a, v| a.max(v.abs()));
    let exp = if (1e-3..1e4).contains(&big) {
        0
    } else {
        eng_exponent(big)
    };
    let step_m = step / 10f64.powi(exp);
    let decimals = (-step_m.log10() - 1e-9).ceil().max(0.0) as usize;
    values.iter().map(|v| render(*v, exp, decimals)).collect()
}

/// The label of one value shown on its own (log axes): three significant digits at most,
/// trailing zeros dropped.
pub fn format_single(v: f64) -> String {
    if v == 0.0 || !v.is_finite() {
        return if v == 0.0 { "0".into() } else { v.to_string() };
    }
    let exp = if (1e-3..1e4).contains(&v.abs()) {
        0
    } else {
        eng_exponent(v)
    };
    let m = v / 10f64.powi(exp);
    let digits = 3 - 1 - m.abs().log10().floor() as i32;
    let s = format!("{m:.*}", digits.max(0) as usize);
    let s = if s.contains('.') {
        s.trim_end_matches('0').trim_end_matches('.').to_string()
    } else {
        s
    };
    if exp == 0 { s } else { format!("{s}e{exp}") }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn noisy(s: &str) -> bool {
        s.contains("00000") || s.contains("99999")
    }

    #[test]
    fn linear_ticks_are_round_and_at_least_two() {
        let t = linear(0.0, 1.0);
        assert_eq!(t.labels, ["0", "0.2", "0.4", "0.6", "0.8", "1.0"]);
        let t = linear(1.0e-5, 4.1e-5);
        assert!(t.values.len() >= 2);
        assert!(
            t.labels.iter().all(|l| !noisy(l) && l.ends_with("e-6")),
            "{t:?}"
        );
        assert!(t.labels.contains(&"30e-6".to_string()), "{t:?}");
        let t = linear(-3.3e-4, 3.3e-4);
        assert!(t.labels.contains(&"0".to_string()), "{t:?}");
        // A tiny range still gets two ticks.
        let t = linear(1.0, 1.0 + 1e-9);
        assert!(t.values.len() >= 2, "{t:?}");
        assert!(t.labels.windows(2).all(|w| w[0] != w[1]), "{t:?}");
    }

    #[test]
    fn log_ticks_within_one_decade_use_mantissas() {
        let t = log(1.2e-5, 4.0e-5);
        assert!(t.values.len() >= 2, "{t:?}");
        assert_eq!(t.labels, ["15e-6", "20e-6", "30e-6"]);
        let t = log(3.0, 2000.0);
        assert_eq!(t.labels, ["10", "100", "1000"]);
        let t = log(100.0, 130.0);
        assert!(t.values.len() >= 2, "{t:?}");
        assert!(t.labels.iter().all(|l| !noisy(l)), "{t:?}");
    }

    #[test]
    fn engineering_labels_have_no_float_noise() {
        assert_eq!(format_single(3.0000000000000004e-5), "30e-6");
        assert_eq!(format_single(0.1 + 0.2), "0.3");
        assert_eq!(format_single(250_000.0), "250e3");
        assert_eq!(
            format_axis(&[0.1, 0.2, 0.30000000000000004], 0.1),
            ["0.1", "0.2", "0.3"]
        );
        assert_eq!(format_axis(&[-0.0000000001, 5.0], 5.0), ["0", "5"]);
    }
}
