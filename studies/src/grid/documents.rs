//! The documents of a grid's results: `GRID.md` (a table, and the delivery table of cells with
//! `[guidance]`), `GRID.csv` (one row per cell and filter; a string field is quoted only when it
//! holds a comma or a quote, as most variations do) and `GRID.json` (the cells and every cell's
//! trade report, timing apart).

use crate::grid::row::CellRow;
use crate::grid::run::{GridResults, GridStudy};
use crate::provenance::Provenance;
use crate::trade::csv_series::opt;
use serde_json::{Value, json};
use std::fmt::Write as _;
use std::io::Write;

fn o(v: Option<f64>) -> String {
    v.map(|x| format!("{x:.4}")).unwrap_or_else(|| "–".into())
}

/// `GRID.md`.
pub fn markdown(study: &GridStudy, rows: &[CellRow]) -> String {
    let grid = &study.file;
    let mut md = String::new();
    if study.lincov() {
        let _ = writeln!(
            md,
            "# Grid `{}`\n\nLinCov of each filter along each cell's nominal trajectory (no runs: \
             predicted RMSE and ANEES), filters {}.\n",
            grid.name,
            grid.filters.join(", ")
        );
    } else {
        let _ = writeln!(
            md,
            "# Grid `{}`\n\n{} runs per cell, seed {}, filters {}.\n",
            grid.name,
            grid.runs,
            grid.seed,
            grid.filters.join(", ")
        );
    }
    md.push_str(
        "| cell | scenario | variation | filter | pos RMSE final [m] | vel RMSE final [m/s] | pos RMSE avg [m] | ANEES | min in-3σ | diverged | µs/step | min δ (scaled) |\n",
    );
    md.push_str("|---|---|---|---|---|---|---|---|---|---|---|---|\n");
    for r in rows {
        let _ = match &r.refused {
            Some(why) => writeln!(
                md,
                "| {} | {} | {} | {} | refused: {} ||||||||",
                r.cell, r.scenario, r.variation, r.filter, why
            ),
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
            ),
        };
    }
    delivery_markdown(&mut md, rows);
    md
}

/// The delivery table of `GRID.md` (cells with `[guidance]` only; nothing without them).
fn delivery_markdown(md: &mut String, rows: &[CellRow]) {
    let guided: Vec<_> = rows
        .iter()
        .filter_map(|r| r.delivery.as_ref().map(|d| (r, d)))
        .collect();
    if guided.is_empty() {
        return;
    }
    md.push_str(
        "\n## Delivery at deployment (cells with `[guidance]`)\n\nEach filter flown in the \
         guidance loop on the cell's runs (same seeds), beside perfect navigation on the same \
         runs; misses over the runs that deployed, failures counted apart.\n\n",
    );
    md.push_str(
        "| cell | variation | filter | RMS miss [m] | 99 % ellipse semi-axes a × b [m] | failed | perfect-nav RMS miss [m] | perfect-nav failed |\n",
    );
    md.push_str("|---|---|---|---|---|---|---|---|\n");
    let m = |v: Option<f64>| v.map_or_else(|| "–".into(), |x| format!("{x:.1}"));
    for (r, d) in guided {
        let _ = writeln!(
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
        );
    }
}

/// `GRID.csv`: one row per cell and filter.
pub fn write_csv<W: Write>(w: &mut csv::Writer<W>, rows: &[CellRow]) -> csv::Result<()> {
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
    for r in rows {
        let d = r.delivery.as_ref();
        w.write_record([
            r.cell.clone(),
            r.scenario.clone(),
            r.variation.clone(),
            r.filter.clone(),
            r.refused.clone().unwrap_or_default(),
            opt(r.pos_rmse_final_m),
            opt(r.vel_rmse_final_mps),
            opt(r.pos_rmse_avg_m),
            opt(r.anees),
            opt(r.min_within_3sigma),
            r.diverged.map(|d| d.to_string()).unwrap_or_default(),
            opt(r.us_per_step),
            opt(r.min_delta_scaled),
            opt(d.and_then(|d| d.rms_miss_m)),
            opt(d.and_then(|d| d.ellipse_99_semi_major_m)),
            opt(d.and_then(|d| d.ellipse_99_semi_minor_m)),
            d.map(|d| d.failures.to_string()).unwrap_or_default(),
            opt(d.and_then(|d| d.perfect_nav_rms_miss_m)),
            d.map(|d| d.perfect_nav_failures.to_string())
                .unwrap_or_default(),
        ])?;
    }
    Ok(())
}

/// `GRID.json`: provenance, the grid, its rows and every finished cell's report; the CPU times
/// under `timing`.
pub fn to_json(study: &GridStudy, results: &GridResults, provenance: &Provenance) -> Value {
    let grid = &study.file;
    let rows = &results.rows;
    json!({
        "provenance": provenance,
        "grid": grid.name, "runs": grid.runs, "seed": grid.seed, "cells": rows,
        "method": if study.lincov() { "lincov" } else { "mc" },
        "reports": results.reports.iter().map(|c| json!({"cell": c.cell, "scenario_fingerprint": c.scenario_fingerprint, "report": c.report})).collect::<Vec<_>>(),
        "timing": {
            "us_per_step": rows.iter().filter(|r| r.us_per_step.is_some()).map(|r| json!({"cell": r.cell, "filter": r.filter, "us_per_step": r.us_per_step})).collect::<Vec<_>>(),
        },
    })
}
