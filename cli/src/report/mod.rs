//! Self-contained HTML reports (`trade --report FILE.html`, and the grid report): one page,
//! inline SVG figures and CSS, no scripts and nothing loaded from the network; every text from
//! the study is escaped.

pub mod grid_page;
pub mod html;
pub mod summary;
pub mod trade_page;

use anyhow::Result;
use std::path::Path;

/// Write `html` to `path` (creating its directory) and return the seconds spent on `make`
/// and writing together.
pub fn write(path: &Path, make: impl FnOnce() -> Result<String>) -> Result<f64> {
    let clock = std::time::Instant::now();
    let html = make()?;
    crate::atomic_file::write(path, html)?;
    Ok(clock.elapsed().as_secs_f64())
}

/// The trade report of `report` to `path`; returns the time it took (s).
pub fn write_trade(
    path: &Path,
    report: &entrynav::sim::TradeReport,
    names: &crate::plot::labels::WeightNames,
    provenance: &crate::provenance::Provenance,
    wall_s: f64,
    extra: &crate::plots::ExtraCurves,
    delivery: Option<&entrynav::sim::guided::delivery::DeliveryReport>,
) -> Result<f64> {
    write(path, || {
        let mut figures = crate::plots::trade_figures_with(report, names, extra)?;
        if let Some(d) = delivery {
            figures.extend(crate::delivery_plots::delivery_figures(d)?);
        }
        Ok(trade_page::TradePage {
            report,
            figures: &figures,
            provenance,
            wall_s,
            delivery,
        }
        .html())
    })
}

/// Refuse, before any run, a `--report` path that cannot be written (or `-`: a report is a
/// file).
pub fn check_path(path: Option<&Path>) -> Result<()> {
    let Some(p) = path else { return Ok(()) };
    if crate::exit::is_stdout(p) {
        return Err(
            crate::exit::Usage("--report -: the report is a file; give a path".into()).into(),
        );
    }
    crate::exit::check_output_file(p, "--report")
}
