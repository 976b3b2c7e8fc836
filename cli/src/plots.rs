//! SVG plots (plotters, SVG backend: no system fonts or libraries needed).

use anyhow::{Context, Result};
use entrynav::sim::TradeReport;
use plotters::prelude::*;
use std::path::Path;

/// One curve: legend name, points, dashed or solid.
pub struct Curve {
    /// Legend entry.
    pub name: String,
    /// (x, y) points; non-finite y values are skipped.
    pub points: Vec<(f64, f64)>,
    /// Draw dashed.
    pub dashed: bool,
}

const PALETTE: [RGBColor; 8] = [
    RGBColor(31, 119, 180),
    RGBColor(255, 127, 14),
    RGBColor(44, 160, 44),
    RGBColor(214, 39, 40),
    RGBColor(148, 103, 189),
    RGBColor(140, 86, 75),
    RGBColor(227, 119, 194),
    RGBColor(127, 127, 127),
];

/// A line plot with optional logarithmic y axis.
pub fn line_plot(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    log_y: bool,
    curves: &[Curve],
) -> Result<()> {
    let pts: Vec<(f64, f64)> = curves
        .iter()
        .flat_map(|c| c.points.iter().copied())
        .filter(|(x, y)| x.is_finite() && y.is_finite() && (!log_y || *y > 0.0))
        .collect();
    if pts.is_empty() {
        return Ok(());
    }
    let (x0, x1) = pts.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |a, p| {
        (a.0.min(p.0), a.1.max(p.0))
    });
    let (y0, y1) = pts.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |a, p| {
        (a.0.min(p.1), a.1.max(p.1))
    });
    let x1 = if x1 > x0 { x1 } else { x0 + 1.0 };
    let root = SVGBackend::new(path, (960, 600)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| anyhow::anyhow!("{e}"))?;
    let draw = |root: &DrawingArea<SVGBackend, plotters::coord::Shift>| -> Result<()> {
        let mut builder = ChartBuilder::on(root);
        builder
            .caption(title, ("sans-serif", 22))
            .margin(12)
            .x_label_area_size(45)
            .y_label_area_size(80);
        macro_rules! finish {
            ($chart:expr) => {{
                let mut chart = $chart;
                chart
                    .configure_mesh()
                    .x_desc(x_label)
                    .y_desc(y_label)
                    .draw()
                    .map_err(|e| anyhow::anyhow!("{e}"))?;
                for (i, c) in curves.iter().enumerate() {
                    let color = PALETTE[i % PALETTE.len()];
                    let data: Vec<(f64, f64)> = c
                        .points
                        .iter()
                        .copied()
                        .filter(|(x, y)| x.is_finite() && y.is_finite() && (!log_y || *y > 0.0))
                        .collect();
                    let style = ShapeStyle {
                        color: color.to_rgba(),
                        filled: false,
                        stroke_width: 2,
                    };
                    if c.dashed {
                        chart
                            .draw_series(DashedLineSeries::new(data, 6, 4, style))
                            .map_err(|e| anyhow::anyhow!("{e}"))?
                            .label(c.name.clone())
                            .legend(move |(x, y)| {
                                PathElement::new(vec![(x, y), (x + 20, y)], color)
                            });
                    } else {
                        chart
                            .draw_series(LineSeries::new(data, style))
                            .map_err(|e| anyhow::anyhow!("{e}"))?
                            .label(c.name.clone())
                            .legend(move |(x, y)| {
                                PathElement::new(vec![(x, y), (x + 20, y)], color)
                            });
                    }
                }
                chart
                    .configure_series_labels()
                    .background_style(WHITE.mix(0.8))
                    .border_style(BLACK)
                    .draw()
                    .map_err(|e| anyhow::anyhow!("{e}"))?;
            }};
        }
        if log_y {
            let (lo, hi) = (y0 * 0.8, y1 * 1.25);
            finish!(
                builder
                    .build_cartesian_2d(x0..x1, (lo..hi).log_scale())
                    .map_err(|e| anyhow::anyhow!("{e}"))?
            );
        } else {
            let pad = ((y1 - y0) * 0.05).max(1e-12);
            finish!(
                builder
                    .build_cartesian_2d(x0..x1, (y0 - pad)..(y1 + pad))
                    .map_err(|e| anyhow::anyhow!("{e}"))?
            );
        }
        Ok(())
    };
    draw(&root)?;
    root.present()
        .map_err(|e| anyhow::anyhow!("{e}"))
        .with_context(|| format!("writing {}", path.display()))?;
    Ok(())
}

/// The plots of a trade study.
/// The scenario's PCRLB 1σ of `name` vs time, dashed, when the trade has one.
fn pcrlb_curve(report: &TradeReport, name: &str) -> Option<Curve> {
    let b = report.pcrlb.as_ref().filter(|b| b.available)?;
    let v = b.series.get(name)?;
    Some(Curve {
        name: "PCRLB".into(),
        points: b.times_s.iter().copied().zip(v.iter().copied()).collect(),
        dashed: true,
    })
}

pub fn trade_plots(dir: &Path, report: &TradeReport) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let sc = &report.scenario;
    let series_points =
        |f: &entrynav::sim::FilterReport, get: &dyn Fn(usize) -> Option<f64>| -> Vec<(f64, f64)> {
            f.series
                .times_s
                .iter()
                .enumerate()
                .filter_map(|(k, t)| get(k).map(|v| (*t, v)))
                .collect()
        };
    // RMSE vs time per state, all filters, and the scenario's PCRLB (dashed).
    for (i, st) in report.states.iter().enumerate() {
        let mut curves: Vec<Curve> = report
            .filters
            .iter()
            .map(|f| Curve {
                name: f.name.clone(),
                points: series_points(f, &|k| f.series.rmse[k][i]),
                dashed: false,
            })
            .collect();
        curves.extend(pcrlb_curve(report, st));
        line_plot(
            &dir.join(format!("{sc}_rmse_{st}.svg")),
            &format!("{sc}: RMSE of {st}"),
            "t [s]",
            st,
            true,
            &curves,
        )?;
    }
    for (name, get) in [("pos_m", 0usize), ("vel_mps", 1usize)] {
        let mut curves: Vec<Curve> = report
            .filters
            .iter()
            .map(|f| Curve {
                name: f.name.clone(),
                points: series_points(f, &|k| {
                    if get == 0 {
                        f.series.pos_rmse_m[k]
                    } else {
                        f.series.vel_rmse_mps[k]
                    }
                }),
                dashed: false,
            })
            .collect();
        curves.extend(pcrlb_curve(report, name));
        line_plot(
            &dir.join(format!("{sc}_rmse_{name}.svg")),
            &format!("{sc}: RMS {name} error"),
            "t [s]",
            name,
            true,
            &curves,
        )?;
    }
    // Errors against 3σ envelopes, per filter and state.
    for f in &report.filters {
        for (i, st) in report.states.iter().enumerate() {
            let curves = vec![
                Curve {
                    name: "RMSE".into(),
                    points: series_points(f, &|k| f.series.rmse[k][i]),
                    dashed: false,
                },
                Curve {
                    name: "mean error".into(),
                    points: series_points(f, &|k| f.series.bias[k][i]),
                    dashed: false,
                },
                Curve {
                    name: "+3σ (mean)".into(),
                    points: series_points(f, &|k| f.series.sigma_mean[k][i].map(|s| 3.0 * s)),
                    dashed: true,
                },
                Curve {
                    name: "-3σ (mean)".into(),
                    points: series_points(f, &|k| f.series.sigma_mean[k][i].map(|s| -3.0 * s)),
                    dashed: true,
                },
            ];
            line_plot(
                &dir.join(format!("{sc}_{}_err3s_{st}.svg", f.name)),
                &format!("{sc} / {}: {st} error and 3σ", f.name),
                "t [s]",
                st,
                false,
                &curves,
            )?;
        }
    }
    // NEES with bounds.
    let mut curves: Vec<Curve> = report
        .filters
        .iter()
        .map(|f| Curve {
            name: f.name.clone(),
            points: series_points(f, &|k| f.series.nees_mean[k]),
            dashed: false,
        })
        .collect();
    if let Some(f) = report.filters.first() {
        let t: Vec<f64> = f.series.times_s.clone();
        for (b, name) in [
            (f.consistency.nees_bounds_95[0], "95% lower"),
            (f.consistency.nees_bounds_95[1], "95% upper"),
        ] {
            curves.push(Curve {
                name: name.into(),
                points: t.iter().map(|t| (*t, b)).collect(),
                dashed: true,
            });
        }
    }
    line_plot(
        &dir.join(format!("{sc}_nees.svg")),
        &format!("{sc}: mean NEES over runs"),
        "t [s]",
        "NEES",
        true,
        &curves,
    )?;
    // Density error (seed 001 Fig. 10) where estimated.
    let dens: Vec<Curve> = report
        .filters
        .iter()
        .filter(|f| f.density_rmspe_pct.is_some())
        .map(|f| Curve {
            name: f.name.clone(),
            points: series_points(f, &|k| f.series.density_rms_pct[k]),
            dashed: false,
        })
        .collect();
    if !dens.is_empty() {
        line_plot(
            &dir.join(format!("{sc}_density_error.svg")),
            &format!("{sc}: RMS error of the onboard density profile at the true altitude"),
            "t [s]",
            "%",
            true,
            &dens,
        )?;
    }
    // Per filter (seed 001 Fig. 10): mean error of the density profile at the true altitude with
    // its ±RMS envelope over runs, and the RMS error of the density at the filter's estimate.
    for f in report
        .filters
        .iter()
        .filter(|f| f.density_rmspe_pct.is_some())
    {
        let s = &f.series;
        let rms = |k: usize, sign: f64| s.density_rms_pct[k].map(|v| sign * v);
        line_plot(
            &dir.join(format!("{sc}_{}_density_error.svg", f.name)),
            &format!(
                "{sc}, {}: density error (profile at the true altitude)",
                f.name
            ),
            "t [s]",
            "%",
            false,
            &[
                Curve {
                    name: "mean error".into(),
                    points: series_points(f, &|k| s.density_mean_pct[k]),
                    dashed: false,
                },
                Curve {
                    name: "+RMS".into(),
                    points: series_points(f, &|k| rms(k, 1.0)),
                    dashed: true,
                },
                Curve {
                    name: "-RMS".into(),
                    points: series_points(f, &|k| rms(k, -1.0)),
                    dashed: true,
                },
                Curve {
                    name: "RMS at the estimate".into(),
                    points: series_points(f, &|k| s.density_at_estimate_rms_pct[k]),
                    dashed: false,
                },
            ],
        )?;
    }
    // Fusion weights / model probabilities.
    for f in &report.filters {
        let nw = f
            .series
            .weights_mean
            .iter()
            .map(|w| w.len())
            .max()
            .unwrap_or(0);
        if nw == 0 {
            continue;
        }
        let curves: Vec<Curve> = (0..nw)
            .map(|j| Curve {
                name: format!("w{j}"),
                points: series_points(f, &|k| f.series.weights_mean[k].get(j).copied()),
                dashed: false,
            })
            .collect();
        line_plot(
            &dir.join(format!("{sc}_{}_weights.svg", f.name)),
            &format!("{sc} / {}: mean weights", f.name),
            "t [s]",
            "weight",
            false,
            &curves,
        )?;
    }
    Ok(())
}
