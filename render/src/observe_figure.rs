//! The SVG figure of an observability analysis (`entrynav observe --plot`), from the study's result: δ(t) raw and scaled on a
//! log axis, and the geometry index I(t) with `--fim`.

use crate::error::{RenderError, Result};
use entrynav::observability::{DegreeSeries, FimEpoch};
use entrynav::scenario::Scenario;

/// The plot as SVG text.
pub fn observe_figure(
    scenario: &Scenario,
    central: &DegreeSeries,
    subsystems: &[&DegreeSeries],
    fim: Option<&[FimEpoch]>,
) -> Result<String> {
    let mut svg = String::new();
    draw(&mut svg, scenario, central, subsystems, fim)?;
    Ok(svg)
}

/// The plot of [`observe_figure`] drawn into `svg`.
fn draw(
    svg: &mut String,
    scenario: &Scenario,
    central: &DegreeSeries,
    subsystems: &[&DegreeSeries],
    fim: Option<&[FimEpoch]>,
) -> Result<()> {
    use plotters::prelude::*;
    let err = |e: &dyn std::fmt::Display| RenderError::Draw(e.to_string());
    let panels = if fim.is_some() { 3 } else { 2 };
    let root = SVGBackend::with_string(svg, (1000, 380 * panels)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let areas = root.split_evenly((panels as usize, 1));
    let t_end = central.samples.last().map_or(1.0, |s| s.t).max(1e-9);
    let mut series: Vec<&DegreeSeries> = vec![central];
    series.extend_from_slice(subsystems);
    for (area, scaled) in areas.iter().zip([false, true]) {
        let pts: Vec<Vec<(f64, f64)>> = series
            .iter()
            .map(|s| {
                s.times()
                    .into_iter()
                    .zip(s.deltas(scaled))
                    .filter(|(_, d)| *d > 0.0 && d.is_finite())
                    .collect()
            })
            .collect();
        let all = pts.iter().flatten().map(|p| p.1);
        let (lo, hi) = all.fold((f64::INFINITY, 0.0_f64), |a, d| (a.0.min(d), a.1.max(d)));
        let (lo, hi) = if lo.is_finite() {
            (lo / 2.0, hi * 2.0)
        } else {
            (1e-20, 1.0)
        };
        // At least two decades, so that the log axis gets labelled ticks.
        let (lo, hi) = if hi / lo < 100.0 {
            let c = (lo * hi).sqrt();
            (c / 10.0, c * 10.0)
        } else {
            (lo, hi)
        };
        let label = if scaled { "scaled δ" } else { "raw SI δ" };
        let mut chart = ChartBuilder::on(area)
            .caption(
                format!(
                    "{}: {label} = σmin/σmax ({}; δ = 0 not drawn)",
                    scenario.config.name,
                    central.method.name()
                ),
                ("sans-serif", 20),
            )
            .margin(10)
            .x_label_area_size(40)
            .y_label_area_size(80)
            .build_cartesian_2d(0.0..t_end, (lo..hi).log_scale())
            .map_err(|e| err(&e))?;
        chart
            .configure_mesh()
            .x_desc("t [s]")
            .y_desc(label)
            .y_label_formatter(&|v| format!("{v:.0e}"))
            .draw()
            .map_err(|e| err(&e))?;
        for (i, (s, p)) in series.iter().zip(pts).enumerate() {
            let color = Palette99::pick(i).to_rgba();
            let name = if p.is_empty() {
                format!("{} (δ = 0 throughout: rank-deficient)", s.name)
            } else {
                s.name.clone()
            };
            chart
                .draw_series(LineSeries::new(p, color.stroke_width(2)))
                .map_err(|e| err(&e))?
                .label(name)
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], color));
        }
        chart
            .configure_series_labels()
            .background_style(WHITE.mix(0.8))
            .border_style(BLACK)
            .draw()
            .map_err(|e| err(&e))?;
    }
    if let Some(f) = fim {
        index_panel(&areas[2], f, t_end)?;
    }
    root.present().map_err(|e| err(&e))?;
    Ok(())
}

/// The panel of the geometry index I(t) (seed 002 eq. 54).
fn index_panel(
    area: &plotters::drawing::DrawingArea<
        plotters::prelude::SVGBackend<'_>,
        plotters::coord::Shift,
    >,
    f: &[FimEpoch],
    t_end: f64,
) -> Result<()> {
    use plotters::prelude::*;
    let err = |e: &dyn std::fmt::Display| RenderError::Draw(e.to_string());
    let top = f.iter().map(|e| e.geometry_index).fold(0.0_f64, f64::max);
    let mut chart = ChartBuilder::on(area)
        .caption(
            "geometry index I = Σ [n_i·(n_j × n_k)]² (seed 002 eq. 54)",
            ("sans-serif", 20),
        )
        .margin(10)
        .x_label_area_size(40)
        .y_label_area_size(80)
        .build_cartesian_2d(0.0..t_end, 0.0..(top * 1.1).max(1e-12))
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .x_desc("t [s]")
        .y_desc("I")
        .draw()
        .map_err(|e| err(&e))?;
    chart
        .draw_series(LineSeries::new(
            f.iter().map(|e| (e.t, e.geometry_index)),
            BLUE.stroke_width(2),
        ))
        .map_err(|e| err(&e))?;
    Ok(())
}
