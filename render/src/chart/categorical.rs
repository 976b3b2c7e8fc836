//! Values per category (grid cells) as dodged markers on a categorical x axis: one tick per
//! category labelled with its name, one marker colour per series, no line between categories.

use super::axis::Axis;
use super::legend::{self, Entry, Mark};
use super::line::{Chart, y_axis};
use super::line::{
    Frame, bounds, caption_size, draw_mesh, plot_err, render, split_legend, y_range,
};
use super::ticks::{self, Ticks};
use crate::error::Result;
use plotters::prelude::*;

/// One series over the categories: `values[i]` belongs to category `i` (`None`: no value).
pub struct Series {
    /// Legend entry.
    pub name: String,
    /// One value per category.
    pub values: Vec<Option<f64>>,
}

/// A categorical chart of `series` over `categories`; `None` when there is no value to draw.
pub fn category_chart(
    frame: &Frame,
    categories: &[String],
    series: &[Series],
) -> Result<Option<String>> {
    let usable = |v: &f64| v.is_finite() && (!frame.log_y || *v > 0.0);
    let Some((y0, y1)) = bounds(
        series
            .iter()
            .flat_map(|s| s.values.iter().flatten().copied())
            .filter(usable),
    ) else {
        return Ok(None);
    };
    let (lo, hi) = y_range(y0, y1, frame.log_y);
    let n = categories.len().max(1);
    let xt = Ticks {
        values: (0..n).map(|i| i as f64).collect(),
        labels: categories.to_vec(),
    };
    let yt = if frame.log_y {
        ticks::log(lo, hi)
    } else {
        ticks::linear(lo, hi)
    };
    let width = 0.6 / series.len().max(1) as f64;
    let offset = |j: usize| -0.3 + width * (j as f64 + 0.5);
    let points: Vec<Vec<(f64, f64)>> = series
        .iter()
        .enumerate()
        .map(|(j, s)| {
            s.values
                .iter()
                .enumerate()
                .filter_map(|(i, v)| v.filter(usable).map(|v| (i as f64 + offset(j), v)))
                .collect()
        })
        .collect();
    let svg = render(frame.size, |root| {
        let names: Vec<&str> = series.iter().map(|s| s.name.as_str()).collect();
        let (plot, side) = split_legend(root, &names);
        let mut builder = ChartBuilder::on(&plot);
        builder
            .caption(frame.title, ("sans-serif", caption_size(frame.size.0)))
            .margin(super::line::MARGIN)
            .x_label_area_size(48)
            .y_label_area_size(86);
        let x = Axis::linear(-0.5, n as f64 - 0.5, &xt.values);
        let y = y_axis(lo, hi, frame.log_y, &yt);
        let mut chart = builder.build_cartesian_2d(x, y).map_err(plot_err)?;
        draw_markers(&mut chart, frame, &xt, &yt, &points)?;
        let entries: Vec<Entry> = names
            .iter()
            .enumerate()
            .map(|(i, name)| Entry {
                name,
                color: i,
                mark: Mark::Dot,
            })
            .collect();
        legend::draw(&side, &entries, 50).map_err(plot_err)
    })?;
    Ok(Some(svg))
}

fn draw_markers(
    chart: &mut Chart,
    frame: &Frame,
    xt: &Ticks,
    yt: &Ticks,
    points: &[Vec<(f64, f64)>],
) -> Result<()> {
    draw_mesh(chart, frame, xt, yt)?;
    for (j, pts) in points.iter().enumerate() {
        let c = legend::color(j);
        chart
            .draw_series(pts.iter().map(|p| Circle::new(*p, 5, c.filled())))
            .map_err(plot_err)?;
    }
    Ok(())
}
