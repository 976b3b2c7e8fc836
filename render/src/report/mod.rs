//! Self-contained HTML reports (`trade --report FILE.html`, and the grid report): one page,
//! inline SVG figures and CSS, no scripts and nothing loaded from the network; every text from
//! the study is escaped.

pub mod grid_page;
pub mod html;
pub mod summary;
pub mod trade_page;

use crate::chart::labels::WeightNames;
use crate::error::Result;
use crate::trade_figures::{ExtraCurves, trade_figures_with};
use entrynav::sim::TradeReport;
use entrynav::sim::guided::delivery::DeliveryReport;
use entrynav_studies::provenance::Provenance;

/// The trade report of `report` (the study ran `wall_s` seconds; `extra`: LinCov curves beside
/// the Monte Carlo's; `delivery`: a scenario with `[guidance]`).
pub fn trade_report(
    report: &TradeReport,
    names: &WeightNames,
    provenance: &Provenance,
    wall_s: f64,
    extra: &ExtraCurves,
    delivery: Option<&DeliveryReport>,
) -> Result<String> {
    let mut figures = trade_figures_with(report, names, extra)?;
    if let Some(d) = delivery {
        figures.extend(crate::delivery_figures::delivery_figures(d)?);
    }
    Ok(trade_page::TradePage {
        report,
        figures: &figures,
        provenance,
        wall_s,
        delivery,
    }
    .html())
}
