//! Consistency figures of a trade: the mean NEES and NIS over runs against their χ² bands, and
//! per filter the NIS of every measurement channel over time against its own band (issue 49:
//! which sensor the filter misjudges, and when).

use crate::chart::{Curve, line_chart};
use crate::error::Result;
use crate::figure::Kind;
use crate::figure_parts::{Out, WIDE, curve, frame, series_points};
use entrynav::sim::nees_bounds_95;
use entrynav::sim::{FilterReport, TradeReport};

/// Mean NEES and NIS over runs with their two-sided 95 % χ² bands.
pub(crate) fn consistency_figures(report: &TradeReport, out: &mut Out) -> Result<()> {
    for (nis, file) in [(false, "nees"), (true, "nis")] {
        let mut curves: Vec<Curve> = report
            .filters
            .iter()
            .map(|f| {
                let s = &f.series;
                let pts = series_points(f, &|k| if nis { s.nis_mean[k] } else { s.nees_mean[k] });
                curve(f.name.clone(), pts, false)
            })
            .collect();
        // Each filter's own two-sided band: filters with another dof (a fusion filter's NIS sums
        // its local filters' innovations) get their own pair, named after them.
        let mut bands: Vec<([f64; 2], String, Vec<&str>, &FilterReport)> = Vec::new();
        for f in &report.filters {
            let c = &f.consistency;
            let (b, dof) = if nis {
                (
                    c.nis_bounds_95,
                    c.nis_dof.map_or("-".into(), |d| format!("{d:.1}")),
                )
            } else {
                (c.nees_bounds_95, c.nees_dof.to_string())
            };
            match bands.iter_mut().find(|(bb, d, _, _)| *bb == b && *d == dof) {
                Some(band) => band.2.push(&f.name),
                None => bands.push((b, dof, vec![&f.name], f)),
            }
        }
        let several = bands.len() > 1;
        for (b, dof, names, f) in &bands {
            let whose = if several {
                format!(", {}", names.join(", "))
            } else {
                String::new()
            };
            for (v, side) in [(b[0], "lower"), (b[1], "upper")] {
                if !v.is_finite() {
                    continue;
                }
                let pts = f.series.times_s.iter().map(|t| (*t, v)).collect();
                curves.push(curve(
                    format!("χ² 95 % {side} (dof {dof}{whose})"),
                    pts,
                    true,
                ));
            }
        }
        let (title, y) = if nis {
            ("mean NIS over runs", "NIS (1)")
        } else {
            ("mean NEES over runs", "NEES (1)")
        };
        let kind = if nis { Kind::Nis } else { Kind::Nees };
        let svg = line_chart(&frame(title, y, true, WIDE), &curves)?;
        out.push(file.into(), kind, svg);
    }
    Ok(())
}

/// Per filter, each channel's ν²/s term averaged over the runs at every epoch, with the 95 %
/// band of that mean for a consistent filter (χ²(runs)/runs, dashed) and 1.
pub(crate) fn channel_figures(report: &TradeReport, out: &mut Out) -> Result<()> {
    for f in &report.filters {
        let s = &f.series;
        let mut curves: Vec<Curve> = s
            .channel_nis_mean
            .iter()
            .enumerate()
            .filter(|(_, series)| series.iter().any(Option::is_some))
            .map(|(c, series)| {
                let name = report
                    .channels
                    .get(c)
                    .cloned()
                    .unwrap_or_else(|| format!("channel{c}"));
                curve(
                    name,
                    series_points(f, &|k| series.get(k).copied().flatten()),
                    false,
                )
            })
            .collect();
        if curves.is_empty() {
            continue;
        }
        let (lo, hi) = nees_bounds_95(1, f.runs.max(1) as usize);
        for (v, side) in [(lo, "lower"), (hi, "upper")] {
            let pts = s.times_s.iter().map(|t| (*t, v)).collect();
            curves.push(curve(
                format!("χ² 95 % {side} (one channel, {} runs)", f.runs),
                pts,
                true,
            ));
        }
        let title = format!("{}: NIS per channel over runs", f.name);
        let svg = line_chart(&frame(&title, "ν²/s (1)", true, WIDE), &curves)?;
        out.push(
            format!("{}_nis_channels", f.name),
            Kind::ChannelNis(f.name.clone()),
            svg,
        );
    }
    Ok(())
}
