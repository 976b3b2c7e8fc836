//! Self-contained HTML reports (`trade --report FILE.html`, and the grid report): one page,
//! inline SVG figures and CSS, no scripts and nothing loaded from the network; every text from
//! the study is escaped.

pub mod grid_page;
pub mod html;
pub mod summary;
pub mod trade_page;

use crate::chart::labels::WeightNames;
use crate::error::Result;
use crate::trade_figures::{lincov_curves, trade_figures_with};
use entrynav::sim::TradeReport;
use entrynav::sim::guided::delivery::DeliveryReport;
use entrynav_studies::provenance::Provenance;
use entrynav_studies::trade::lincov_comparison::LinCovComparison;

/// The trade report of `report` (the study ran `wall_s` seconds; `lincov`: LinCov beside the
/// Monte Carlo, `trade --method both`, its table and its curves in the RMSE charts; `delivery`:
/// a scenario with `[guidance]`).
pub fn trade_report(
    report: &TradeReport,
    names: &WeightNames,
    provenance: &Provenance,
    wall_s: f64,
    lincov: Option<&LinCovComparison>,
    delivery: Option<&DeliveryReport>,
) -> Result<String> {
    let extra = lincov.map(|c| lincov_curves(c, report)).unwrap_or_default();
    let mut figures = trade_figures_with(report, names, &extra)?;
    if let Some(d) = delivery {
        figures.extend(crate::delivery_figures::delivery_figures(d)?);
    }
    Ok(trade_page::TradePage {
        report,
        figures: &figures,
        provenance,
        wall_s,
        lincov,
        delivery,
    }
    .html())
}
