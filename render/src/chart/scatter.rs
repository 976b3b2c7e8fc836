//! A scatter of points per series with an optional closed outline (the 3σ ellipse) per series,
//! equal spans on both axes so an ellipse keeps its shape.

use super::axis::Axis;
use super::legend::{self, Entry, Mark};
use super::line::{Frame, bounds, caption_size, draw_mesh, plot_err, render, split_legend};
use super::ticks;
use crate::error::Result;
use plotters::prelude::*;

/// One series: points and an outline drawn dashed in the same colour.
pub struct Cloud {
    /// Legend entry.
    pub name: String,
    /// (x, y) points.
    pub points: Vec<(f64, f64)>,
    /// Closed outline (e.g. the 3σ ellipse); empty for none.
    pub outline: Vec<(f64, f64)>,
}

/// The outline of the ellipse centred at `c` with semi-axes `a` ≥ `b` and the major axis at
/// `angle_rad` from the x axis toward y.
pub fn ellipse(c: (f64, f64), a: f64, b: f64, angle_rad: f64) -> Vec<(f64, f64)> {
    let (s, k) = angle_rad.sin_cos();
    (0..=96)
        .map(|i| {
            let phi = i as f64 / 96.0 * std::f64::consts::TAU;
            let (u, v) = (a * phi.cos(), b * phi.sin());
            (c.0 + u * k - v * s, c.1 + u * s + v * k)
        })
        .collect()
}

/// A scatter chart; `None` when there is no finite point.
pub fn scatter_chart(frame: &Frame, clouds: &[Cloud]) -> Result<Option<String>> {
    let all: Vec<(f64, f64)> = clouds
        .iter()
        .flat_map(|c| c.points.iter().chain(&c.outline).copied())
        .filter(|(x, y)| x.is_finite() && y.is_finite())
        .collect();
    let (Some((x0, x1)), Some((y0, y1))) = (
        bounds(all.iter().map(|p| p.0)),
        bounds(all.iter().map(|p| p.1)),
    ) else {
        return Ok(None);
    };
    let half = ((x1 - x0).max(y1 - y0) * 0.55).max(1e-9);
    let (cx, cy) = ((x0 + x1) / 2.0, (y0 + y1) / 2.0);
    let (xr, yr) = ((cx - half, cx + half), (cy - half, cy + half));
    let (xt, yt) = (ticks::linear(xr.0, xr.1), ticks::linear(yr.0, yr.1));
    let svg = render(frame.size, |root| {
        let names: Vec<&str> = clouds.iter().map(|c| c.name.as_str()).collect();
        let (plot, side) = split_legend(root, &names);
        let mut chart = ChartBuilder::on(&plot)
            .caption(frame.title, ("sans-serif", caption_size(frame.size.0)))
            .margin(super::line::MARGIN)
            .x_label_area_size(48)
            .y_label_area_size(86)
            .build_cartesian_2d(
                Axis::linear(xr.0, xr.1, &xt.values),
                Axis::linear(yr.0, yr.1, &yt.values),
            )
            .map_err(plot_err)?;
        draw_mesh(&mut chart, frame, &xt, &yt)?;
        for (i, c) in clouds.iter().enumerate() {
            let col = legend::color(i);
            chart
                .draw_series(
                    c.points
                        .iter()
                        .filter(|(x, y)| x.is_finite() && y.is_finite())
                        .map(|p| Circle::new(*p, 3, col.mix(0.6).filled())),
                )
                .map_err(plot_err)?;
            if !c.outline.is_empty() {
                chart
                    .draw_series(DashedLineSeries::new(
                        c.outline.clone(),
                        6,
                        4,
                        col.stroke_width(2),
                    ))
                    .map_err(plot_err)?;
            }
        }
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

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn ellipse_outline_has_the_semi_axes() {
        let e = ellipse((1.0, 2.0), 3.0, 1.0, std::f64::consts::FRAC_PI_2);
        // Major axis along y: the farthest point in y is 3 from the centre, in x 1.
        let dy = e.iter().map(|p| (p.1 - 2.0).abs()).fold(0.0, f64::max);
        let dx = e.iter().map(|p| (p.0 - 1.0).abs()).fold(0.0, f64::max);
        assert!(
            (dy - 3.0).abs() < 1e-9 && (dx - 1.0).abs() < 1e-3,
            "{dx} {dy}"
        );
    }
}
