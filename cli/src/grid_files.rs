//! The report of `entrynav trade --grid` in `--out-dir`: `GRID.md` (a table), `GRID.json` (the
//! cells and every cell's trade report), `GRID.csv`, the SVG figures, and the HTML page of
//! `--report`. All are rewritten after every finished cell.

use crate::grid::{CellRow, GridFile};
use anyhow::Result;
use entrynav::sim::TradeReport;
use std::io::Write;
use std::path::Path;

/// `GRID.csv`: one row per cell and filter (a string field is quoted only when it holds a comma
/// or a quote, as most variations do).
fn write_rows_csv(w: &mut crate::csv_file::FileWriter, rows: &[CellRow]) -> Result<()> {
    w.write_record([
        "cell",
        "scenario",
        "variation",
        "filter",
        "refused",
        "pos_rmse_final_m",
        "vel_rmse_final_mps",
        "pos_rmse_avg_m",
        "anees",
        "min_within_3sigma",
        "diverged",
        "us_per_step",
        "min_delta_scaled",
        "delivery_rms_miss_m",
        "delivery_ellipse99_semi_major_m",
        "delivery_ellipse99_semi_minor_m",
        "delivery_failures",
        "perfect_nav_rms_miss_m",
        "perfect_nav_failures",
    ])?;
    let c = crate::csv_file::opt;
    for r in rows {
        w.write_record([
            r.cell.clone(),
            r.scenario.clone(),
            r.variation.clone(),
            r.filter.clone(),
            r.refused.clone().unwrap_or_default(),
            c(r.pos_rmse_final_m),
            c(r.vel_rmse_final_mps),
            c(r.pos_rmse_avg_m),
            c(r.anees),
            c(r.min_within_3sigma),
            r.diverged.map(|d| d.to_string()).unwrap_or_default(),
            c(r.us_per_step),
            c(r.min_delta_scaled),
            c(r.delivery.as_ref().and_then(|d| d.rms_miss_m)),
            c(r.delivery.as_ref().and_then(|d| d.ellipse_99_semi_major_m)),
            c(r.delivery.as_ref().and_then(|d| d.ellipse_99_semi_minor_m)),
            r.delivery
                .as_ref()
                .map(|d| d.failures.to_string())
                .unwrap_or_default(),
            c(r.delivery.as_ref().and_then(|d| d.perfect_nav_rms_miss_m)),
            r.delivery
                .as_ref()
                .map(|d| d.perfect_nav_failures.to_string())
                .unwrap_or_default(),
        ])?;
    }
    Ok(())
}

fn o(v: Option<f64>) -> String {
    v.map(|x| format!("{x:.4}")).unwrap_or_else(|| "–".into())
}

/// Write every file of the grid's report from the cells finished so far (`cells_total`: the
/// grid's size; `html`: the `--report` page).
pub fn write_outputs(
    grid: &GridFile,
    out: &Path,
    rows: &[CellRow],
    reports: &[(String, String, TradeReport)],
    (cells_total, html): (usize, Option<&Path>),
) -> Result<()> {
    let provenance = entrynav_studies::provenance::Provenance::new(std::env::args().collect(), &[]);
    let md_path = out.join(format!("{}.md", grid.name));
    let mut md = entrynav_studies::output::atomic_file::AtomicFile::create(&md_path)?;
    if grid.lincov {
        writeln!(
            md,
            "# Grid `{}`\n\nLinCov of each filter along each cell's nominal trajectory (no runs: \
             predicted RMSE and ANEES), filters {}.\n",
            grid.name,
            grid.filters.join(", ")
        )?;
    } else {
        writeln!(
            md,
            "# Grid `{}`\n\n{} runs per cell, seed {}, filters {}.\n",
            grid.name,
            grid.runs,
            grid.seed,
            grid.filters.join(", ")
        )?;
    }
    writeln!(
        md,
        "| cell | scenario | variation | filter | pos RMSE final [m] | vel RMSE final [m/s] | pos RMSE avg [m] | ANEES | min in-3σ | diverged | µs/step | min δ (scaled) |"
    )?;
    writeln!(md, "|---|---|---|---|---|---|---|---|---|---|---|---|")?;
    for r in rows {
        match &r.refused {
            Some(why) => writeln!(
                md,
                "| {} | {} | {} | {} | refused: {} ||||||||",
                r.cell, r.scenario, r.variation, r.filter, why
            )?,
            None => writeln!(
                md,
                "| {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} | {} |",
                r.cell,
                r.scenario,
                r.variation,
                r.filter,
                o(r.pos_rmse_final_m),
                o(r.vel_rmse_final_mps),
                o(r.pos_rmse_avg_m),
                o(r.anees),
                o(r.min_within_3sigma),
                r.diverged.map(|d| d.to_string()).unwrap_or_default(),
                o(r.us_per_step),
                r.min_delta_scaled
                    .map(|d| format!("{d:.3e}"))
                    .unwrap_or_else(|| "–".into())
            )?,
        }
    }
    write_delivery_md(&mut md, rows)?;
    md.commit()?;
    let json_path = out.join(format!("{}.json", grid.name));
    entrynav_studies::output::atomic_file::write(
        &json_path,
        serde_json::to_string_pretty(&serde_json::json!({
            "provenance": &provenance,
            "grid": grid.name, "runs": grid.runs, "seed": grid.seed, "cells": rows,
            "method": if grid.lincov { "lincov" } else { "mc" },
            "reports": reports.iter().map(|(c, fp, r)| serde_json::json!({"cell": c, "scenario_fingerprint": fp, "report": r})).collect::<Vec<_>>(),
            "timing": {
                "us_per_step": rows.iter().filter(|r| r.us_per_step.is_some()).map(|r| serde_json::json!({"cell": r.cell, "filter": r.filter, "us_per_step": r.us_per_step})).collect::<Vec<_>>(),
            },
        }))? + "\n",
    )?;
    crate::csv_file::write(&out.join(format!("{}.csv", grid.name)), |w| {
        write_rows_csv(w, rows)
    })?;
    let figures = crate::grid_plots::grid_figures(&grid.name, &grid.filters, rows)?;
    for fig in &figures {
        let path = out.join(&fig.file);
        entrynav_studies::output::atomic_file::write(&path, &fig.svg)?;
    }
    if let Some(path) = html {
        let page = crate::report::grid_page::GridPage {
            name: &grid.name,
            runs: grid.runs,
            seed: grid.seed,
            filters: &grid.filters,
            rows,
            reports,
            cells_total,
            figures: &figures,
            provenance: serde_json::to_value(&provenance)?,
        };
        crate::report::write(path, || Ok(page.html()))?;
    }
    Ok(())
}

/// The delivery table of `GRID.md` (cells with `[guidance]` only; nothing without them).
fn write_delivery_md(md: &mut impl Write, rows: &[CellRow]) -> Result<()> {
    let guided: Vec<_> = rows
        .iter()
        .filter_map(|r| r.delivery.as_ref().map(|d| (r, d)))
        .collect();
    if guided.is_empty() {
        return Ok(());
    }
    writeln!(
        md,
        "\n## Delivery at deployment (cells with `[guidance]`)\n\nEach filter flown in the \
         guidance loop on the cell's runs (same seeds), beside perfect navigation on the same \
         runs; misses over the runs that deployed, failures counted apart.\n"
    )?;
    writeln!(
        md,
        "| cell | variation | filter | RMS miss [m] | 99 % ellipse semi-axes a × b [m] | failed | perfect-nav RMS miss [m] | perfect-nav failed |"
    )?;
    writeln!(md, "|---|---|---|---|---|---|---|---|")?;
    let m = |v: Option<f64>| v.map_or_else(|| "–".into(), |x| format!("{x:.1}"));
    for (r, d) in guided {
        writeln!(
            md,
            "| {} | {} | {} | {} | {} × {} | {} | {} | {} |",
            r.cell,
            r.variation,
            r.filter,
            m(d.rms_miss_m),
            m(d.ellipse_99_semi_major_m),
            m(d.ellipse_99_semi_minor_m),
            d.failures,
            m(d.perfect_nav_rms_miss_m),
            d.perfect_nav_failures
        )?;
    }
    Ok(())
}
