//! SVG figures rendered to strings (plotters' SVG backend: no fonts or system libraries):
//! line charts, categorical charts, scatter plots with ellipses; ticks, labels and legends
//! chosen for a reader. Writing a file is the front end's.

pub mod axis;
pub mod categorical;
pub mod labels;
pub mod legend;
pub mod line;
pub mod scatter;
#[cfg(test)]
pub mod svg_text;
#[cfg(test)]
mod tests;
pub mod ticks;

pub use line::{Curve, Frame, line_chart};

/// A line chart of `curves` in the standard 960 × 540 frame (`None` when no curve has a
/// drawable point).
pub fn line_plot(
    title: &str,
    x_label: &str,
    y_label: &str,
    log_y: bool,
    curves: &[Curve],
) -> crate::error::Result<Option<String>> {
    let frame = Frame {
        title,
        x_label,
        y_label,
        log_y,
        size: (960, 540),
    };
    line_chart(&frame, curves)
}
