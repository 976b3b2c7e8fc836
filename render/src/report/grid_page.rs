//! The HTML report of a grid study (`trade --grid FILE.toml --report FILE.html`): the cell
//! table, the categorical figures per metric, each cell's consistency verdicts, provenance.

use super::html::{self, Cell, escape, figures, note, num, section, table};
use super::summary;
use crate::grid_figures::GridFigure;
use entrynav_studies::grid::row::CellRow;
use entrynav_studies::grid::run::CellReport;

/// A grid report's content.
pub struct GridPage<'a> {
    /// Grid name.
    pub name: &'a str,
    /// Runs per cell and seed.
    pub runs: usize,
    /// Master seed.
    pub seed: u64,
    /// Filters asked for.
    pub filters: &'a [String],
    /// One row per cell and filter.
    pub rows: &'a [CellRow],
    /// Finished cells: label, scenario fingerprint, report.
    pub reports: &'a [CellReport],
    /// Cells in the grid.
    pub cells_total: usize,
    /// The figures (`grid_plots::grid_figures`).
    pub figures: &'a [GridFigure],
    /// Where it came from.
    pub provenance: serde_json::Value,
}

impl GridPage<'_> {
    fn cell_table(&self) -> String {
        let rows: Vec<Vec<Cell>> = self
            .rows
            .iter()
            .map(|r| {
                let mut row = vec![
                    Cell::text(r.cell.clone()),
                    Cell::text(r.scenario.clone()),
                    Cell::text(r.variation.clone()),
                    Cell::text(r.filter.clone()),
                ];
                match &r.refused {
                    Some(why) => row.push(Cell::text(format!("refused: {why}"))),
                    None => row.extend([
                        Cell::num(num(r.pos_rmse_final_m)),
                        Cell::num(num(r.vel_rmse_final_mps)),
                        Cell::num(num(r.pos_rmse_avg_m)),
                        Cell::num(num(r.anees)),
                        Cell::num(num(r.min_within_3sigma)),
                        Cell::num(r.diverged.map(|d| d.to_string()).unwrap_or_default()),
                        Cell::num(num(r.us_per_step)),
                        Cell::num(num(r.min_delta_scaled)),
                    ]),
                }
                row
            })
            .collect();
        table(
            &[
                "cell",
                "scenario",
                "variation",
                "filter",
                "pos RMSE final (m)",
                "vel RMSE final (m/s)",
                "pos RMSE avg (m)",
                "ANEES",
                "min inside ±3σ",
                "diverged",
                "µs per step",
                "min δ (scaled)",
            ],
            &rows,
        )
    }

    fn consistency(&self) -> String {
        let mut s = String::new();
        for c in self.reports {
            s += &format!(
                "<h3>{} ({}, fingerprint {})</h3>\n",
                escape(&c.cell),
                escape(&c.report.scenario),
                escape(&c.scenario_fingerprint)
            );
            s += &summary::consistency_table(&c.report);
        }
        s
    }

    /// The page.
    pub fn html(&self) -> String {
        let done = self.reports.len();
        let status = if done < self.cells_total {
            format!(" — {done} of {} cells finished (partial)", self.cells_total)
        } else {
            String::new()
        };
        let intro = format!(
            "<p>{} runs per cell, seed {}, filters <b>{}</b>{}.</p>\n",
            self.runs,
            self.seed,
            escape(&self.filters.join(", ")),
            escape(&status)
        );
        let mut body = section("summary", "Cells", &(intro + &self.cell_table()));
        body += &section(
            "metrics",
            "Metrics per cell",
            &(note("One marker per filter in each cell; the cells are listed in the table.")
                + &figures(self.figures.iter().map(|f| f.svg.as_str()))),
        );
        body += &section("consistency", "Consistency per cell", &self.consistency());
        body += &section(
            "provenance",
            "Provenance",
            &html::json_block(&self.provenance),
        );
        html::page(&format!("entrynav grid report: {}", self.name), &body)
    }
}
