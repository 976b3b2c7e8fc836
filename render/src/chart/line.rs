//! A line chart rendered to an SVG string: chosen ticks on both axes (`ticks.rs`), human axis
//! labels, the legend in a column to the right of the data area (`legend.rs`).

use super::axis::Axis;
use super::legend::{self, Entry, Mark};
use super::ticks::{self, Ticks};
use crate::error::{RenderError, Result};
use plotters::coord::Shift;
use plotters::prelude::*;

/// One curve: legend name, points, dashed or solid.
#[derive(Debug, Clone)]
pub struct Curve {
    /// Legend entry.
    pub name: String,
    /// (x, y) points; non-finite y values are skipped.
    pub points: Vec<(f64, f64)>,
    /// Draw dashed.
    pub dashed: bool,
    /// Palette index ([`super::legend::PALETTE`]); `None`: the curve's position in the chart.
    /// A prediction drawn beside what it predicts takes its colour (LinCov beside its filter).
    pub color: Option<usize>,
}

/// Title, axis labels, scale and pixel size of a figure.
pub struct Frame<'a> {
    /// Caption.
    pub title: &'a str,
    /// x axis label with its unit, e.g. `time (s)`.
    pub x_label: &'a str,
    /// y axis label with its unit.
    pub y_label: &'a str,
    /// Logarithmic y axis.
    pub log_y: bool,
    /// Width and height (px).
    pub size: (u32, u32),
}

/// Margin around the chart (px).
pub const MARGIN: u32 = 10;

/// A plotters error as a [`RenderError`].
pub fn plot_err(e: impl std::fmt::Display) -> RenderError {
    RenderError::Plot(e.to_string())
}

/// Render `draw` on a white SVG canvas of `size` and return the SVG text.
pub fn render(
    size: (u32, u32),
    draw: impl FnOnce(&DrawingArea<SVGBackend, Shift>) -> Result<()>,
) -> Result<String> {
    let mut svg = String::new();
    {
        let root = SVGBackend::with_string(&mut svg, size).into_drawing_area();
        root.fill(&WHITE).map_err(plot_err)?;
        draw(&root)?;
        root.present().map_err(plot_err)?;
    }
    Ok(svg)
}

/// The chart area and the legend column of `root` for a legend with these names.
pub fn split_legend<'a>(
    root: &DrawingArea<SVGBackend<'a>, Shift>,
    names: &[&str],
) -> (
    DrawingArea<SVGBackend<'a>, Shift>,
    DrawingArea<SVGBackend<'a>, Shift>,
) {
    let (w, _) = root.dim_in_pixel();
    root.split_horizontally(w.saturating_sub(legend::width(names)))
}

/// Caption font size for a figure of width `w`.
pub fn caption_size(w: u32) -> u32 {
    if w < 700 { 15 } else { 19 }
}

fn finite(points: &[(f64, f64)], log_y: bool) -> Vec<(f64, f64)> {
    points
        .iter()
        .copied()
        .filter(|(x, y)| x.is_finite() && y.is_finite() && (!log_y || *y > 0.0))
        .collect()
}

/// Bounds (min, max) of an iterator of values.
pub fn bounds(values: impl Iterator<Item = f64>) -> Option<(f64, f64)> {
    values.fold(None, |a, v| match a {
        None => Some((v, v)),
        Some((lo, hi)) => Some((lo.min(v), hi.max(v))),
    })
}

/// The y range drawn for data in `[y0, y1]`.
pub fn y_range(y0: f64, y1: f64, log_y: bool) -> (f64, f64) {
    if log_y {
        let (lo, hi) = (y0 * 0.8, y1 * 1.25);
        if hi > lo * 1.01 {
            (lo, hi)
        } else {
            (lo * 0.9, hi * 1.1)
        }
    } else {
        let pad = ((y1 - y0) * 0.05)
            .max(y0.abs().max(y1.abs()) * 1e-6)
            .max(1e-300);
        (y0 - pad, y1 + pad)
    }
}

/// A line chart of `curves`; `None` when no curve has a drawable point.
pub fn line_chart(frame: &Frame, curves: &[Curve]) -> Result<Option<String>> {
    let data: Vec<Vec<(f64, f64)>> = curves
        .iter()
        .map(|c| finite(&c.points, frame.log_y))
        .collect();
    let all = || data.iter().flatten();
    let (Some((x0, x1)), Some((y0, y1))) = (bounds(all().map(|p| p.0)), bounds(all().map(|p| p.1)))
    else {
        return Ok(None);
    };
    let x1 = if x1 > x0 { x1 } else { x0 + 1.0 };
    let (lo, hi) = y_range(y0, y1, frame.log_y);
    let xt = ticks::linear(x0, x1);
    let yt = if frame.log_y {
        ticks::log(lo, hi)
    } else {
        ticks::linear(lo, hi)
    };
    let svg = render(frame.size, |root| {
        let names: Vec<&str> = curves.iter().map(|c| c.name.as_str()).collect();
        let (plot, side) = split_legend(root, &names);
        let mut builder = ChartBuilder::on(&plot);
        builder
            .caption(frame.title, ("sans-serif", caption_size(frame.size.0)))
            .margin(MARGIN)
            .x_label_area_size(48)
            .y_label_area_size(86);
        let x = Axis::linear(x0, x1, &xt.values);
        let y = y_axis(lo, hi, frame.log_y, &yt);
        let chart = builder.build_cartesian_2d(x, y).map_err(plot_err)?;
        draw_lines(chart, frame, &xt, &yt, curves, &data)?;
        let entries: Vec<Entry> = curves
            .iter()
            .enumerate()
            .map(|(i, c)| Entry {
                name: &c.name,
                color: c.color.unwrap_or(i),
                mark: if c.dashed { Mark::Dashed } else { Mark::Line },
            })
            .collect();
        legend::draw(&side, &entries, 50).map_err(plot_err)
    })?;
    Ok(Some(svg))
}

/// A chart on our axes.
pub type Chart<'a, 'b> = ChartContext<'a, SVGBackend<'b>, Cartesian2d<Axis, Axis>>;

/// The y axis over `lo..hi` with ticks `yt`.
pub fn y_axis(lo: f64, hi: f64, log_y: bool, yt: &Ticks) -> Axis {
    if log_y {
        Axis::log(lo, hi, &yt.values)
    } else {
        Axis::linear(lo, hi, &yt.values)
    }
}

/// Draw the mesh with the chosen tick labels and axis descriptions.
pub fn draw_mesh(chart: &mut Chart, frame: &Frame, xt: &Ticks, yt: &Ticks) -> Result<()> {
    let xf = |v: &f64| xt.label_of(*v);
    let yf = |v: &f64| yt.label_of(*v);
    chart
        .configure_mesh()
        .x_desc(frame.x_label)
        .y_desc(frame.y_label)
        .x_label_formatter(&xf)
        .y_label_formatter(&yf)
        .label_style(("sans-serif", 13))
        .axis_desc_style(("sans-serif", 15))
        .bold_line_style(BLACK.mix(0.12))
        .draw()
        .map_err(plot_err)
}

fn draw_lines(
    mut chart: Chart,
    frame: &Frame,
    xt: &Ticks,
    yt: &Ticks,
    curves: &[Curve],
    data: &[Vec<(f64, f64)>],
) -> Result<()> {
    draw_mesh(&mut chart, frame, xt, yt)?;
    for (i, (c, pts)) in curves.iter().zip(data).enumerate() {
        let style = legend::color(c.color.unwrap_or(i)).stroke_width(2);
        if c.dashed {
            chart
                .draw_series(DashedLineSeries::new(pts.clone(), 6, 4, style))
                .map_err(plot_err)?;
        } else {
            chart
                .draw_series(LineSeries::new(pts.clone(), style))
                .map_err(plot_err)?;
        }
    }
    Ok(())
}
