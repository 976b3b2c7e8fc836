//! SVG figures rendered to strings (plotters' SVG backend: no fonts or system libraries):
//! line charts, categorical charts, scatter plots with ellipses; ticks, labels and legends
//! chosen for a reader. Writing a file is the caller's thin wrapper.

pub mod axis;
pub mod categorical;
pub mod chart;
pub mod labels;
pub mod legend;
pub mod scatter;
#[cfg(test)]
pub mod svg_text;
#[cfg(test)]
mod tests;
pub mod ticks;

pub use chart::{Curve, Frame, line_chart};

/// Write a line chart of `curves` to `path` (nothing when no curve has a drawable point).
pub fn line_plot(
    path: &std::path::Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    log_y: bool,
    curves: &[Curve],
) -> anyhow::Result<()> {
    let frame = Frame {
        title,
        x_label,
        y_label,
        log_y,
        size: (960, 540),
    };
    if let Some(svg) = line_chart(&frame, curves)? {
        entrynav_studies::output::atomic_file::write(path, svg)?;
    }
    Ok(())
}
