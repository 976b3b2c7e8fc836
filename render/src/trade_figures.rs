//! The figures of a trade study, each an SVG string (`trade_figures`), and `trade_plots`, the
//! thin wrapper that writes them to `--plots DIR`. The HTML report (`report/`) embeds the same
//! strings.

use crate::chart::labels::{WeightNames, axis, quantity};
use crate::chart::scatter::{Cloud, ellipse, scatter_chart};
use crate::chart::{Curve, Frame, line_chart};
use crate::consistency_figures::{channel_figures, consistency_figures};
use crate::error::Result;
use crate::figure::{Figure, Kind};
use crate::figure_parts::{Out, curve, frame, series_points};
pub use crate::figure_parts::{SMALL, WIDE};
use entrynav::sim::{FilterReport, TradeReport};

/// The scenario's PCRLB 1σ of `name` vs time, dashed, when the trade has one.
fn pcrlb_curve(report: &TradeReport, name: &str) -> Option<Curve> {
    let b = report.pcrlb.as_ref().filter(|b| b.available)?;
    let v = b.series.get(name)?;
    let pts = b.times_s.iter().copied().zip(v.iter().copied()).collect();
    Some(curve("PCRLB", pts, true))
}

/// Every figure of `report`; `names` names the weights.
#[cfg(test)]
pub fn trade_figures(report: &TradeReport, names: &WeightNames) -> Result<Vec<Figure>> {
    trade_figures_with(report, names, &ExtraCurves::new())
}

/// Curves drawn into a trade's RMSE charts beside the Monte Carlo's, by metric (a state name,
/// `pos_m`, `vel_mps`): LinCov's predictions of `trade --method both`.
pub type ExtraCurves = std::collections::BTreeMap<String, Vec<Curve>>;

/// Every figure of a trade, with `extra` curves in the RMSE charts.
pub fn trade_figures_with(
    report: &TradeReport,
    names: &WeightNames,
    extra: &ExtraCurves,
) -> Result<Vec<Figure>> {
    let sc = report.scenario.as_str();
    let mut out = Out {
        sc,
        figures: Vec::new(),
    };
    // RMSE vs time per state, position and velocity; all filters and the PCRLB (dashed).
    let metrics: Vec<&str> = report
        .states
        .iter()
        .map(String::as_str)
        .chain(["pos_m", "vel_mps", "downrange_m", "crossrange_m", "up_m"])
        .collect();
    for (i, st) in metrics.iter().enumerate() {
        let mut curves: Vec<Curve> = report
            .filters
            .iter()
            .map(|f| {
                let pts = series_points(f, &|k| match *st {
                    "pos_m" => f.series.pos_rmse_m[k],
                    "vel_mps" => f.series.vel_rmse_mps[k],
                    "downrange_m" => f.series.local_rmse_m.first().and_then(|s| s[k]),
                    "crossrange_m" => f.series.local_rmse_m.get(1).and_then(|s| s[k]),
                    "up_m" => f.series.local_rmse_m.get(2).and_then(|s| s[k]),
                    _ => f.series.rmse[k][i],
                });
                curve(f.name.clone(), pts, false)
            })
            .collect();
        curves.extend(extra.get(*st).into_iter().flatten().cloned());
        curves.extend(pcrlb_curve(report, st));
        let title = format!("{}: RMSE over runs", quantity(st).0);
        let y = axis(st, "error RMSE");
        let svg = line_chart(&frame(&title, &y, true, WIDE), &curves)?;
        out.push(format!("rmse_{st}"), Kind::Rmse, svg);
    }
    // Errors against 3σ envelopes, per filter and state: |error| and σ on a log axis, so that an
    // error of 1000 m at the start and one of 0.3 m late in the flight are both readable.
    for f in &report.filters {
        for (i, st) in report.states.iter().enumerate() {
            let s = &f.series;
            let sig = |k: usize| s.sigma_mean[k][i].map(|v| 3.0 * v);
            let curves = vec![
                curve("RMSE", series_points(f, &|k| s.rmse[k][i]), false),
                curve(
                    "|mean error|",
                    series_points(f, &|k| s.bias[k][i].map(f64::abs)),
                    false,
                ),
                curve("3σ (mean σ)", series_points(f, &|k| sig(k)), true),
            ];
            let title = format!("{}: {}", f.name, quantity(st).0);
            let y = axis(st, "|error|");
            let svg = line_chart(&frame(&title, &y, true, SMALL), &curves)?;
            out.push(
                format!("{}_err3s_{st}", f.name),
                Kind::ErrorSigma(f.name.clone()),
                svg,
            );
        }
    }
    consistency_figures(report, &mut out)?;
    channel_figures(report, &mut out)?;
    density_figures(report, &mut out)?;
    weight_figures(report, names, &mut out)?;
    dispersion_figures(report, &mut out)?;
    Ok(out.figures)
}

/// Density errors (seed 001 Fig. 10) where a filter estimates the density.
fn density_figures(report: &TradeReport, out: &mut Out) -> Result<()> {
    let dens: Vec<&FilterReport> = report
        .filters
        .iter()
        .filter(|f| f.density_rmspe_pct.is_some())
        .collect();
    let curves: Vec<Curve> = dens
        .iter()
        .map(|f| {
            let pts = series_points(f, &|k| f.series.density_rms_pct[k]);
            curve(f.name.clone(), pts, false)
        })
        .collect();
    let title = "RMS error of the onboard density at the true altitude";
    let svg = line_chart(&frame(title, "density error RMS (%)", true, WIDE), &curves)?;
    out.push("density_error".into(), Kind::Density, svg);
    for f in dens {
        let s = &f.series;
        let rms = |k: usize, sign: f64| s.density_rms_pct[k].map(|v| sign * v);
        let curves = [
            curve(
                "mean error",
                series_points(f, &|k| s.density_mean_pct[k]),
                false,
            ),
            curve("+RMS", series_points(f, &|k| rms(k, 1.0)), true),
            curve("−RMS", series_points(f, &|k| rms(k, -1.0)), true),
            curve(
                "RMS at the estimate",
                series_points(f, &|k| s.density_at_estimate_rms_pct[k]),
                false,
            ),
        ];
        let title = format!("{}: density error (profile at the true altitude)", f.name);
        let svg = line_chart(&frame(&title, "density error (%)", false, WIDE), &curves)?;
        out.push(format!("{}_density_error", f.name), Kind::Density, svg);
    }
    Ok(())
}

/// Mean fusion weights (named by beacon) or model probabilities (named by bank member).
fn weight_figures(report: &TradeReport, names: &WeightNames, out: &mut Out) -> Result<()> {
    for f in &report.filters {
        let w = &f.series.weights_mean;
        let nw = w.iter().map(Vec::len).max().unwrap_or(0);
        if nw == 0 {
            continue;
        }
        let (labels, what) = names.labels(&f.name, nw);
        let curves: Vec<Curve> = labels
            .iter()
            .enumerate()
            .map(|(j, l)| {
                curve(
                    l.clone(),
                    series_points(f, &|k| w[k].get(j).copied()),
                    false,
                )
            })
            .collect();
        let title = format!("{}: mean {what} over runs", f.name);
        let y = format!("{what} (1)");
        let svg = line_chart(&frame(&title, &y, false, WIDE), &curves)?;
        out.push(
            format!("{}_weights", f.name),
            Kind::Weights(f.name.clone()),
            svg,
        );
    }
    Ok(())
}

/// Most runs drawn per filter in the dispersion scatter (the ellipse is over all runs).
const MAX_DOTS: usize = 2000;

/// Per filter (each on its own scale: a diverging filter would squash the others): every run's
/// final downrange/crossrange error with the 3σ ellipse.
fn dispersion_figures(report: &TradeReport, out: &mut Out) -> Result<()> {
    for f in &report.filters {
        let cloud = Cloud {
            name: f.name.clone(),
            points: f
                .final_errors
                .iter()
                .filter_map(|r| r.downrange_crossrange_m)
                .take(MAX_DOTS)
                .collect(),
            outline: f.ellipse_km.as_ref().map_or_else(Vec::new, |e| {
                ellipse(
                    (1e3 * e.mean_downrange_km, 1e3 * e.mean_crossrange_km),
                    1e3 * e.semi_major_km,
                    1e3 * e.semi_minor_km,
                    e.orientation_deg.to_radians(),
                )
            }),
        };
        let shown = if f.final_errors.len() > MAX_DOTS {
            format!("first {MAX_DOTS} runs")
        } else {
            "every run".to_string()
        };
        let title = format!(
            "{}: final position error, {shown}; 3σ ellipse dashed",
            f.name
        );
        let frame = Frame {
            title: &title,
            x_label: "downrange error (m)",
            y_label: "crossrange error (m)",
            log_y: false,
            size: (640, 520),
        };
        let svg = scatter_chart(&frame, &[cloud])?;
        out.push(format!("{}_dispersion", f.name), Kind::Dispersion, svg);
    }
    Ok(())
}

/// Every figure of `report`, and the delivery footprints of `delivery` (a scenario with
/// `[guidance]`): what `trade --plots DIR` writes, one file per figure.
pub fn trade_plots(
    report: &TradeReport,
    names: &WeightNames,
    extra: &ExtraCurves,
    delivery: Option<&entrynav::sim::guided::delivery::DeliveryReport>,
) -> Result<Vec<Figure>> {
    let mut figs = trade_figures_with(report, names, extra)?;
    if let Some(d) = delivery {
        figs.extend(crate::delivery_figures::delivery_figures(d)?);
    }
    Ok(figs)
}

/// LinCov's RMSE curves of `trade --method both`, dashed and named "`<filter> LinCov`", per metric
/// (every state, `pos_m`, `vel_mps`), for the RMSE charts, each in the colour of its filter's
/// Monte Carlo curve (the filters are the charts' first curves, in `report`'s order).
pub fn lincov_curves(
    c: &entrynav_studies::trade::lincov_comparison::LinCovComparison,
    report: &TradeReport,
) -> ExtraCurves {
    let color_of = |name: &str| {
        report
            .filters
            .iter()
            .position(|f| name.strip_suffix(" LinCov") == Some(f.name.as_str()))
    };
    c.curves()
        .into_iter()
        .map(|(metric, curves)| {
            let curves = curves
                .into_iter()
                .map(|(name, points)| Curve {
                    color: color_of(&name),
                    name,
                    points,
                    dashed: true,
                })
                .collect();
            (metric, curves)
        })
        .collect()
}
