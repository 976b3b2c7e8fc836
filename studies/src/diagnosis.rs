//! Where and why a filter is inconsistent, in words an engineer acts on: the figure outside its
//! target, the measurement channel and its innovations against their predicted variance, the
//! states least often inside their ±3σ, the longest stretches of epochs above and below the NEES
//! band, and the likely cause. `tune` names a written tuning's remaining problems with it
//! (`crate::tune::verdict`), `trade` prints it under each filter's table and in its report.
//!
//! The targets are deliberately wider than the χ² bands: ANEES/dof and ANIS/dof within
//! [0.7, 1.5], each channel's NIS/dof within [0.5, 2], at least half of the epochs inside the
//! per-epoch NEES band.

use entrynav::sim::monte_carlo::report::FilterReport;

/// ANEES/dof and ANIS/dof a consistent filter should show (and a written tuning reach).
pub const CONSISTENT: (f64, f64) = (0.7, 1.5);
/// NIS/dof of one measurement channel, likewise.
pub const CHANNEL_CONSISTENT: (f64, f64) = (0.5, 2.0);
/// Share of epochs inside the NEES band below which a filter is flagged.
pub const MIN_IN_BAND: f64 = 0.5;

/// What is inconsistent about `f` (`states`: its state names, in report order), one phrase per
/// problem naming the figure, the channel or states, the epochs and the likely cause; empty for a
/// filter inside every target.
pub fn diagnose(f: &FilterReport, states: &[String]) -> Vec<String> {
    let mut out = Vec::new();
    let outside = |v: f64, (lo, hi): (f64, f64)| !(lo..=hi).contains(&v);
    let nees = f
        .consistency
        .anees
        .map(|a| a / f.consistency.nees_dof.max(1) as f64);
    let channels_off: Vec<(&String, f64, Option<f64>)> = f
        .consistency
        .nis_per_channel
        .iter()
        .map(|(name, c)| (name, c.anis_per_dof, c.epochs_in_band_frac))
        .filter(|(_, v, _)| v.is_finite() && outside(*v, CHANNEL_CONSISTENT))
        .collect();
    let nis_off = f
        .consistency
        .anis_per_dof
        .is_some_and(|v| outside(v, CONSISTENT));
    if let Some(v) = nees.filter(|v| outside(*v, CONSISTENT)) {
        let cause = if v > CONSISTENT.1 && !channels_off.is_empty() {
            "the channels below"
        } else if v > CONSISTENT.1 && nis_off {
            "its innovations are too large as well, on every channel alike: the filter's σ \
             (Q, P0) or its assumed measurement noise too small"
        } else if v > CONSISTENT.1 {
            "its innovations are consistent, so the errors the measurements do not see are larger \
             than its process noise says: an unestimated parameter (L/D, β, density) or too \
             small a Q on the states named"
        } else {
            "σ larger than the errors: process noise or P0 too large, conservative"
        };
        out.push(format!(
            "ANEES/dof {v:.3} outside [{}, {}]{} ({cause})",
            CONSISTENT.0,
            CONSISTENT.1,
            worst_states(f, states)
        ));
    }
    if let Some(v) = f
        .consistency
        .anis_per_dof
        .filter(|v| outside(*v, CONSISTENT))
    {
        out.push(format!(
            "ANIS/dof {v:.3} outside [{}, {}]",
            CONSISTENT.0, CONSISTENT.1
        ));
    }
    for (name, v, in_band) in channels_off {
        let epochs = in_band.map_or(String::new(), |b| {
            format!("; {:.0} % of its epochs inside its band", 100.0 * b)
        });
        out.push(format!(
            "{name} innovations {} their predicted variance (NIS/dof {v:.3}, outside [{}, {}]{epochs}): {}",
            times(v),
            CHANNEL_CONSISTENT.0,
            CHANNEL_CONSISTENT.1,
            channel_cause(name, v)
        ));
    }
    if let Some(frac) = f
        .consistency
        .nees_in_bounds_frac
        .filter(|v| *v < MIN_IN_BAND)
    {
        out.push(format!(
            "{:.0} % of epochs inside the NEES band (at least {:.0} % wanted){}",
            100.0 * frac,
            100.0 * MIN_IN_BAND,
            epochs_outside(f)
        ));
    }
    out
}

/// "2700×" or "0.31×".
fn times(v: f64) -> String {
    if v >= 10.0 {
        format!("{v:.0}×")
    } else if v >= 0.1 {
        format!("{v:.2}×")
    } else {
        format!("{v:.3}×")
    }
}

/// The likely cause of channel `name`'s NIS/dof `v` outside its band.
fn channel_cause(name: &str, v: f64) -> &'static str {
    let high = v > 1.0;
    match (name, high) {
        (n, true) if n.starts_with("accel") => {
            "an unmodelled lift or density error (L/D, β or density not estimated and not in Q)"
        }
        (n, false) if n.starts_with("accel") => {
            "the assumed accelerometer noise, or the filter's σ (Q, P0), too large"
        }
        (n, true) if n.starts_with("range") => {
            "a beacon position, clock or range error larger than the assumed noise"
        }
        (n, false) if n.starts_with("range") => {
            "the assumed range noise, or the filter's σ (Q, P0), too large"
        }
        (_, true) => "an airdata or density error larger than the assumed noise",
        (_, false) => "the assumed measurement noise, or the filter's σ (Q, P0), too large",
    }
}

/// ", worst: r_m 61 % inside 3σ, …": up to three states with the lowest share of samples inside
/// their ±3σ, where under 95 %.
fn worst_states(f: &FilterReport, states: &[String]) -> String {
    let mut inside: Vec<(&String, f64)> = states
        .iter()
        .filter_map(|s| Some((s, f.within_3sigma_frac.get(s).copied().flatten()?)))
        .filter(|(_, v)| *v < 0.95)
        .collect();
    inside.sort_by(|a, b| a.1.total_cmp(&b.1));
    if inside.is_empty() {
        return String::new();
    }
    let named: Vec<String> = inside
        .iter()
        .take(3)
        .map(|(s, v)| format!("{s} {:.0} % inside 3σ", 100.0 * v))
        .collect();
    format!(", worst: {}", named.join(", "))
}

/// " (above it over 52–110 s, below it over …)": the longest stretch of epochs above and below
/// the band.
fn epochs_outside(f: &FilterReport) -> String {
    let (t, nees) = (&f.series.times_s, &f.series.nees_mean);
    let [lo, hi] = f.consistency.nees_bounds_95;
    let longest = |pred: &dyn Fn(f64) -> bool| {
        let (mut best, mut start) = (None::<(usize, usize)>, None::<usize>);
        for k in 0..=nees.len() {
            let on = k < nees.len() && nees[k].is_some_and(pred);
            match (on, start) {
                (true, None) => start = Some(k),
                (false, Some(s)) => {
                    if best.is_none_or(|(a, b)| k - s > b - a) {
                        best = Some((s, k));
                    }
                    start = None;
                }
                _ => {}
            }
        }
        best.filter(|(s, e)| *e > *s && *e <= t.len())
            .map(|(s, e)| format!("{:.0}–{:.0} s", t[s], t[e - 1]))
    };
    let mut parts = Vec::new();
    if let Some(span) = longest(&|v| v > hi) {
        parts.push(format!("longest above the band: {span}"));
    }
    if let Some(span) = longest(&|v| v < lo) {
        parts.push(format!("longest below: {span}"));
    }
    if parts.is_empty() {
        String::new()
    } else {
        format!(" ({})", parts.join(", "))
    }
}
