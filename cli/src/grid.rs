//! `entrynav trade --grid FILE.toml`: scenarios × variations × filters in one study (the grid
//! file's format and the study: `entrynav_studies::grid`), one report in `--out-dir`: `GRID.md`
//! (a table), `GRID.json` (the cells and every cell's trade report), `GRID.csv`, the SVG figures,
//! and the HTML page of `--report`. All are rewritten after every finished cell, so an
//! interrupted grid keeps its cells.

use crate::preflight::check_output_dir;
use anyhow::{Context, Result};
use entrynav_studies::grid::documents::{markdown, to_json, write_csv};
use entrynav_studies::grid::run::{GridOptions, GridResults, GridStudy, run_grid};
use entrynav_studies::output::atomic_file::write;
use entrynav_studies::progress::Step;
use entrynav_studies::provenance::Provenance;
use entrynav_studies::trade::options::Method;
use std::path::Path;

/// Run the grid in `grid_path` by `method`; the report goes to `out_dir`, and an HTML page to
/// `html` if given (rewritten after every finished cell, so an interrupted grid keeps its cells
/// there too). `quiet`: no per-cell lines.
pub fn run(
    grid_path: &Path,
    method: Method,
    out_dir: &Path,
    html: Option<&Path>,
    quiet: bool,
) -> Result<()> {
    check_output_dir(out_dir, "--out-dir")?;
    crate::report::check_path(html)?;
    let study = GridStudy::load(grid_path, &GridOptions { method })?;
    std::fs::create_dir_all(out_dir)
        .with_context(|| format!("cannot create {}", out_dir.display()))?;
    let progress = |s: Step<'_>| {
        if !quiet && s.unit == "cells" {
            eprintln!("[{}/{}] {}", s.done + 1, s.total, s.task);
        }
    };
    let mut warned = 0;
    let results = run_grid(&study, Some(crate::interrupt::install()), &progress, |r| {
        for w in &r.warnings[warned..] {
            eprintln!("warning: {w}");
        }
        warned = r.warnings.len();
        write_outputs(&study, out_dir, r, html)
    })?;
    let place = out_dir.display().to_string();
    if let Some(e) = results.interruption(study.cells.len(), &place) {
        return Err(e.into());
    }
    write_outputs(&study, out_dir, &results, html)?;
    println!(
        "grid {}: {} cells, report in {}",
        study.file.name,
        study.cells.len(),
        out_dir.display()
    );
    Ok(())
}

/// Write every file of the grid's report from the cells finished so far (`html`: the `--report`
/// page).
fn write_outputs(
    study: &GridStudy,
    out: &Path,
    results: &GridResults,
    html: Option<&Path>,
) -> Result<()> {
    let grid = &study.file;
    let rows = &results.rows;
    let provenance = Provenance::new(std::env::args().collect(), &[]);
    write(
        &out.join(format!("{}.md", grid.name)),
        markdown(study, rows),
    )?;
    let json = serde_json::to_string_pretty(&to_json(study, results, &provenance))? + "\n";
    write(&out.join(format!("{}.json", grid.name)), json)?;
    crate::csv_file::write(&out.join(format!("{}.csv", grid.name)), |w| {
        Ok(write_csv(w, rows)?)
    })?;
    let figures = entrynav_render::grid_figures::grid_figures(&grid.name, &grid.filters, rows)?;
    for fig in &figures {
        write(&out.join(&fig.file), &fig.svg)?;
    }
    if let Some(path) = html {
        let page = entrynav_render::report::grid_page::GridPage {
            name: &grid.name,
            runs: grid.runs,
            seed: grid.seed,
            filters: &grid.filters,
            rows,
            reports: &results.reports,
            cells_total: study.cells.len(),
            figures: &figures,
            provenance: serde_json::to_value(&provenance)?,
        };
        crate::report::write(path, || Ok(page.html()))?;
    }
    Ok(())
}
