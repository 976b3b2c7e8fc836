//! Writing the HTML reports the render crate draws (`trade --report FILE.html`, the grid's), and
//! refusing a report path before any run.

use anyhow::Result;
use entrynav_render::chart::labels::WeightNames;
use entrynav_studies::provenance::Provenance;
use entrynav_studies::trade::lincov_comparison::LinCovComparison;
use std::path::Path;

/// Write `html` to `path` (creating its directory) and return the seconds spent on `make`
/// and writing together.
pub fn write(path: &Path, make: impl FnOnce() -> Result<String>) -> Result<f64> {
    let clock = std::time::Instant::now();
    let html = make()?;
    entrynav_studies::output::atomic_file::write(path, html)?;
    Ok(clock.elapsed().as_secs_f64())
}

/// The trade report of `report` to `path`; returns the time it took (s).
pub fn write_trade(
    path: &Path,
    report: &entrynav::sim::TradeReport,
    names: &WeightNames,
    provenance: &Provenance,
    wall_s: f64,
    lincov: Option<&LinCovComparison>,
    delivery: Option<&entrynav::sim::guided::delivery::DeliveryReport>,
) -> Result<f64> {
    write(path, || {
        let page = entrynav_render::report::trade_report(
            report, names, provenance, wall_s, lincov, delivery,
        )?;
        Ok(page)
    })
}

/// Refuse, before any run, a `--report` path that cannot be written (or `-`: a report is a
/// file).
pub fn check_path(path: Option<&Path>) -> Result<()> {
    let Some(p) = path else { return Ok(()) };
    if crate::preflight::is_stdout(p) {
        return Err(crate::exit_code::Usage(
            "--report -: the report is a file; give a path".into(),
        )
        .into());
    }
    crate::preflight::check_output_file(p, "--report")
}
