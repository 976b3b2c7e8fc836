//! Writing the figures the render crate draws: a folder of SVG files (`--plots DIR`) and single
//! charts (`--plot FILE`), each file whole or absent.

use anyhow::{Context, Result};
use entrynav::sim::TradeReport;
use entrynav::sim::guided::delivery::DeliveryReport;
use entrynav_render::chart::Curve;
use entrynav_render::chart::labels::WeightNames;
use entrynav_render::figure::Figure;
use entrynav_render::trade_figures::ExtraCurves;
use entrynav_studies::output::atomic_file;
use std::path::Path;

/// Write `figures` into `dir` (created), one file per figure.
pub fn write_figures(dir: &Path, figures: &[Figure]) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    for fig in figures {
        atomic_file::write(&dir.join(&fig.file), &fig.svg)?;
    }
    Ok(())
}

/// `trade --plots DIR`: every figure of `report` (and of `delivery`) into `dir`.
pub fn trade_plots(
    dir: &Path,
    report: &TradeReport,
    names: &WeightNames,
    extra: &ExtraCurves,
    delivery: Option<&DeliveryReport>,
) -> Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
    let figures = entrynav_render::trade_figures::trade_plots(report, names, extra, delivery)?;
    write_figures(dir, &figures)
}

/// Write a line chart of `curves` to `path` (nothing when no curve has a drawable point).
pub fn write_line_plot(
    path: &Path,
    title: &str,
    x_label: &str,
    y_label: &str,
    log_y: bool,
    curves: &[Curve],
) -> Result<()> {
    if let Some(svg) = entrynav_render::chart::line_plot(title, x_label, y_label, log_y, curves)? {
        atomic_file::write(path, svg)?;
    }
    Ok(())
}
