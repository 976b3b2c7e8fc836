//! The figures of a grid study: one categorical chart per metric, a marker per filter in each
//! cell (no line joins cells: they are categories, not a sequence). SVG strings; `grid.rs`
//! writes them and the grid report embeds them.

use crate::chart::Frame;
use crate::chart::categorical::{Series, category_chart};
use crate::error::Result;
use entrynav_studies::grid::row::CellRow;

/// One rendered grid figure.
pub struct GridFigure {
    /// File name in the output directory.
    pub file: String,
    /// The SVG document.
    pub svg: String,
}

type Getter = fn(&CellRow) -> Option<f64>;

/// (file suffix, axis label, log axis, value) of every plotted metric.
const METRICS: [(&str, &str, bool, Getter); 5] = [
    (
        "pos_rmse_final_m",
        "final position error RMSE (m)",
        true,
        |r| r.pos_rmse_final_m,
    ),
    (
        "vel_rmse_final_mps",
        "final velocity error RMSE (m/s)",
        true,
        |r| r.vel_rmse_final_mps,
    ),
    ("anees", "ANEES (1)", true, |r| r.anees),
    ("us_per_step", "CPU time per filter step (µs)", true, |r| {
        r.us_per_step
    }),
    (
        "min_delta_scaled",
        "min scaled observability degree δ (1)",
        true,
        |r| r.min_delta_scaled,
    ),
];

/// The cells in order of first appearance.
fn cells(rows: &[CellRow]) -> Vec<String> {
    let mut out: Vec<String> = Vec::new();
    for r in rows {
        if !out.contains(&r.cell) {
            out.push(r.cell.clone());
        }
    }
    out
}

/// Every figure of a grid named `name` over `filters`.
pub fn grid_figures(name: &str, filters: &[String], rows: &[CellRow]) -> Result<Vec<GridFigure>> {
    let cells = cells(rows);
    let mut out = Vec::new();
    for (metric, label, log_y, get) in METRICS {
        let series: Vec<Series> = filters
            .iter()
            .map(|f| Series {
                name: f.clone(),
                values: cells
                    .iter()
                    .map(|c| {
                        rows.iter()
                            .find(|r| &r.cell == c && &r.filter == f)
                            .and_then(get)
                    })
                    .collect(),
            })
            .collect();
        let title = format!("{name}: {label} per cell");
        let frame = Frame {
            title: &title,
            x_label: "grid cell (see the table)",
            y_label: label,
            log_y,
            size: (900, 460),
        };
        if let Some(svg) = category_chart(&frame, &cells, &series)? {
            out.push(GridFigure {
                file: format!("{name}_{metric}.svg"),
                svg,
            });
        }
    }
    Ok(out)
}
