//! `entrynav trade --grid FILE.toml`: scenarios × variations × filters in one study, one report.
//!
//! ```toml
//! name = "beacon-study"          # report name
//! runs = 200                     # Monte Carlo runs per cell
//! seed = 1
//! filters = ["ekf", "dcifaif"]   # filters that do not fit a cell are listed as refused
//! scenarios = ["four-beacon-fusion", "my-scenario.toml"]
//!
//! [variations]                   # every list multiplies the grid; omitted = no variation
//! beacons = [2, 3, 4]            # keep the first N beacons
//! beacon_fault = [false, true]   # the last beacon goes silent at fault_time_s (default 2/3 of the entry)
//! fault_time_s = 200.0
//! perturbation_scale = [0.0, 1.0] # scale of the truth density perturbation (adds the default one if absent)
//! noise_scale = [1.0, 2.0]       # multiplies every sensor noise (and the filters' assumed noise)
//! beacon_files = ["opt.toml"]    # take the [[beacons]] of these scenario files (e.g. optimizer output)
//! ```

use crate::grid_files::write_outputs;
use anyhow::{Context, Result, bail};
use entrynav::atmosphere::PerturbationConfig;
use entrynav::estimation::nav::FilterKind;
use entrynav::observability::{ChannelSet, Method, Scaling, analysis_points, degree_series};
use entrynav::scenario::ScenarioConfig;
use entrynav::sim::{McOptions, TradeReport, run_trade};
use entrynav_loader as load;
use serde::{Deserialize, Serialize};
use std::path::{Path, PathBuf};

/// A grid file.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct GridFile {
    /// Report name.
    pub name: String,
    /// Runs per cell.
    pub runs: usize,
    /// Master seed (every cell uses it).
    #[serde(default = "one")]
    pub seed: u64,
    /// Filter names.
    pub filters: Vec<String>,
    /// Scenario names or files (relative to the grid file).
    pub scenarios: Vec<String>,
    /// Variations.
    #[serde(default)]
    pub variations: Variations,
    /// `trade --grid … --method lincov`: every cell by LinCov of each filter (no runs).
    #[serde(skip)]
    pub lincov: bool,
}

/// Seconds between rewrites of a LinCov grid's outputs.
const LINCOV_WRITE_EVERY_S: f64 = 5.0;

fn one() -> u64 {
    1
}

/// Variation axes of a grid.
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Variations {
    /// Keep the first N beacons.
    #[serde(default)]
    pub beacons: Vec<usize>,
    /// Last beacon silent from `fault_time_s` on.
    #[serde(default)]
    pub beacon_fault: Vec<bool>,
    /// Fault time (s) (default: 2/3 of the duration).
    #[serde(default)]
    pub fault_time_s: Option<f64>,
    /// Density perturbation scale.
    #[serde(default)]
    pub perturbation_scale: Vec<f64>,
    /// Measurement-noise scale.
    #[serde(default)]
    pub noise_scale: Vec<f64>,
    /// Beacon sets from scenario files.
    #[serde(default)]
    pub beacon_files: Vec<String>,
}

/// One cell's result for one filter.
#[derive(Debug, Serialize)]
pub struct CellRow {
    /// Cell label.
    pub cell: String,
    /// Scenario name.
    pub scenario: String,
    /// Variation values.
    pub variation: String,
    /// Filter name.
    pub filter: String,
    /// Refused (does not fit) — reason.
    pub refused: Option<String>,
    /// Position RMSE at the final epoch (m).
    pub pos_rmse_final_m: Option<f64>,
    /// Velocity RMSE at the final epoch [m/s].
    pub vel_rmse_final_mps: Option<f64>,
    /// Time-averaged position RMSE (m).
    pub pos_rmse_avg_m: Option<f64>,
    /// ANEES.
    pub anees: Option<f64>,
    /// Smallest per-state fraction of samples inside ±3σ.
    pub min_within_3sigma: Option<f64>,
    /// Diverged runs.
    pub diverged: Option<u64>,
    /// CPU per step (µs) (Markdown and CSV; in the JSON it is under `timing`, the one block
    /// that is not reproducible).
    #[serde(skip)]
    pub us_per_step: Option<f64>,
    /// Minimum scaled observability degree of the centralised system along the nominal entry.
    pub min_delta_scaled: Option<f64>,
    /// A Monte Carlo cell with `[guidance]`: the filter's delivery at deployment.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub delivery: Option<crate::grid_delivery::CellDelivery>,
}

struct Cell {
    label: String,
    variation: String,
    config: ScenarioConfig,
    dir: PathBuf,
}

fn noise_scaled(cfg: &mut ScenarioConfig, k: f64) {
    let s = &mut cfg.sensors;
    if let Some(i) = s.imu.as_mut() {
        i.noise_sigma_mps2 *= k;
    }
    if let Some(v) = cfg.filter.imu_sigma_mps2.as_mut() {
        *v *= k;
    }
    if let Some(q) = s.dynamic_pressure.as_mut() {
        q.noise_fraction *= k;
    }
    if let Some(h) = s.heating.as_mut() {
        h.noise_fraction *= k;
    }
    for b in &mut cfg.beacons {
        b.scale_noise(k);
    }
}

fn expand(grid: &GridFile, grid_dir: &Path) -> Result<Vec<Cell>> {
    let v = &grid.variations;
    let axis = |n: usize| if n == 0 { 1 } else { n };
    let mut cells = Vec::new();
    for sc in &grid.scenarios {
        let path = grid_dir.join(sc);
        let name = if path.exists() {
            path.to_string_lossy().to_string()
        } else {
            sc.clone()
        };
        let (base, dir) = load::resolve(&name, load::Base::CurrentDir)?.into_parts();
        for bf in 0..axis(v.beacon_files.len()) {
            for nb in 0..axis(v.beacons.len()) {
                for fault in 0..axis(v.beacon_fault.len()) {
                    for ps in 0..axis(v.perturbation_scale.len()) {
                        for ns in 0..axis(v.noise_scale.len()) {
                            let mut cfg = base.clone();
                            let mut tags = Vec::new();
                            if let Some(file) = v.beacon_files.get(bf) {
                                let (other, _) = load::resolve(
                                    &grid_dir.join(file).to_string_lossy(),
                                    load::Base::CurrentDir,
                                )?
                                .into_parts();
                                cfg.beacons = other.beacons;
                                tags.push(format!("beacons from {file}"));
                            }
                            if let Some(&n) = v.beacons.get(nb) {
                                if n > cfg.beacons.len() {
                                    bail!(
                                        "variations.beacons = {n}: scenario {} has only {} beacons",
                                        cfg.name,
                                        cfg.beacons.len()
                                    );
                                }
                                cfg.beacons.truncate(n);
                                if n == 0 {
                                    cfg.sensors.range = None;
                                    cfg.sensors.range_rate = None;
                                }
                                tags.push(format!("{n} beacons"));
                            }
                            if let Some(&on) = v.beacon_fault.get(fault) {
                                if on {
                                    let t =
                                        v.fault_time_s.unwrap_or(cfg.timing.duration_s * 2.0 / 3.0);
                                    let Some(last) = cfg.beacons.last_mut() else {
                                        bail!(
                                            "variations.beacon_fault: scenario {} has no beacon to fail",
                                            cfg.name
                                        )
                                    };
                                    last.add_outage(t, 1.0e9);
                                    tags.push(format!("fault after {t} s"));
                                } else {
                                    tags.push("no fault".into());
                                }
                            }
                            if let Some(&k) = v.perturbation_scale.get(ps) {
                                let mut p = cfg
                                    .truth
                                    .perturbation
                                    .clone()
                                    .unwrap_or_else(PerturbationConfig::default);
                                p.scale = k;
                                cfg.truth.perturbation = Some(p);
                                tags.push(format!("perturbation x{k}"));
                            }
                            if let Some(&k) = v.noise_scale.get(ns) {
                                noise_scaled(&mut cfg, k);
                                tags.push(format!("noise x{k}"));
                            }
                            let variation = if tags.is_empty() {
                                "nominal".to_string()
                            } else {
                                tags.join(", ")
                            };
                            let text = cfg.to_toml_string();
                            let cfg = ScenarioConfig::from_toml_str(
                                &text,
                                &format!("{} [{variation}]", base.name),
                            )?;
                            let label = format!("c{:02}", cells.len());
                            cells.push(Cell {
                                label,
                                variation,
                                config: cfg,
                                dir: dir.clone(),
                            });
                        }
                    }
                }
            }
        }
    }
    Ok(cells)
}

/// Run a grid file, writing the report into `out_dir`.
/// Run the grid in `grid_path`; the report goes to `out_dir`, and an HTML page to `report` if
/// given as `html` (rewritten after every finished cell, so an interrupted grid keeps its cells there too).
pub fn run(
    grid_path: &Path,
    out_dir: &Path,
    quiet: bool,
    html: Option<&Path>,
    lincov: bool,
) -> Result<()> {
    let text = entrynav_loader::read_text(grid_path)
        .with_context(|| format!("cannot read grid file {}", grid_path.display()))?;
    let mut grid: GridFile =
        toml::from_str(&text).with_context(|| format!("grid file {}", grid_path.display()))?;
    grid.lincov = lincov;
    if grid.runs == 0 {
        bail!("{}: runs must be at least 1", grid_path.display());
    }
    let dir = grid_path
        .parent()
        .map(Path::to_path_buf)
        .unwrap_or_else(|| PathBuf::from("."));
    let cells = expand(&grid, &dir)?;
    std::fs::create_dir_all(out_dir)
        .with_context(|| format!("cannot create {}", out_dir.display()))?;
    let mut rows = Vec::new();
    let mut reports: Vec<(String, String, TradeReport)> = Vec::new();
    let cancel = crate::interrupt::install();
    // A LinCov cell takes milliseconds: its outputs are rewritten every few seconds, not per cell.
    let mut written = std::time::Instant::now();
    for (i, cell) in cells.iter().enumerate() {
        if cancel.load(std::sync::atomic::Ordering::Relaxed) {
            return Err(crate::interrupt::Interrupted(format!(
                "{i} of {} cells in {}",
                cells.len(),
                out_dir.display()
            ))
            .into());
        }
        let scenario = load::build(cell.config.clone(), &cell.dir)?;
        let mut fit = Vec::new();
        for name in &grid.filters {
            let k = FilterKind::parse(name)?;
            match k.misfit(&scenario.onboard) {
                None => fit.push(k),
                Some(reason) => rows.push(CellRow {
                    cell: cell.label.clone(),
                    scenario: scenario.config.name.clone(),
                    variation: cell.variation.clone(),
                    filter: name.clone(),
                    refused: Some(reason),
                    pos_rmse_final_m: None,
                    vel_rmse_final_mps: None,
                    pos_rmse_avg_m: None,
                    anees: None,
                    min_within_3sigma: None,
                    diverged: None,
                    us_per_step: None,
                    min_delta_scaled: None,
                    delivery: None,
                }),
            }
        }
        // The observability column costs ~50 ms a cell (Lie derivatives by jets), five LinCovs'
        // worth: a LinCov grid leaves it out (`observe` gives it per scenario).
        let min_delta = (!grid.lincov)
            .then(|| analysis_points(&scenario, 1.0).ok())
            .flatten()
            .and_then(|pts| {
                degree_series(
                    &scenario,
                    &pts,
                    &ChannelSet::centralised(&scenario),
                    Method::Lie,
                    &Scaling::characteristic(scenario.filter_model()),
                )
                .ok()
            })
            .and_then(|s| s.summary(true))
            .map(|s| s.min);
        if !quiet {
            eprintln!(
                "[{}/{}] {} {} ({}): {} filters × {}",
                i + 1,
                cells.len(),
                cell.label,
                scenario.config.name,
                cell.variation,
                fit.len(),
                if grid.lincov {
                    "LinCov".to_string()
                } else {
                    format!("{} runs", grid.runs)
                }
            );
        }
        if fit.is_empty() {
            continue;
        }
        if grid.lincov {
            for &k in &fit {
                rows.push(crate::grid_lincov::row(
                    &scenario,
                    k,
                    &cell.label,
                    &cell.variation,
                    min_delta,
                ));
            }
            if written.elapsed().as_secs_f64() > LINCOV_WRITE_EVERY_S {
                write_outputs(&grid, out_dir, &rows, &reports, (cells.len(), html))?;
                written = std::time::Instant::now();
            }
            continue;
        }
        let opts = McOptions {
            cancel: Some(cancel),
            ..McOptions::new(grid.runs, grid.seed)
        };
        let report = run_trade(&scenario, &fit, &opts, &|_| {})?;
        if !report.complete {
            // The cell was cut short: the report keeps the cells finished before it.
            return Err(crate::interrupt::Interrupted(format!(
                "{i} of {} cells in {} (cell {} dropped after {} of {} runs)",
                cells.len(),
                out_dir.display(),
                cell.label,
                report.runs_completed,
                report.runs
            ))
            .into());
        }
        let deliveries = crate::grid_delivery::of_cell(&scenario, &fit, grid.runs, grid.seed);
        for f in &report.filters {
            let delivery = deliveries
                .as_ref()
                .and_then(|d| d.iter().find(|(n, _)| *n == f.name))
                .map(|(_, d)| d.clone());
            rows.push(CellRow {
                cell: cell.label.clone(),
                scenario: scenario.config.name.clone(),
                variation: cell.variation.clone(),
                filter: f.name.clone(),
                refused: None,
                pos_rmse_final_m: f.rmse_final.get("pos_m").copied().flatten(),
                vel_rmse_final_mps: f.rmse_final.get("vel_mps").copied().flatten(),
                pos_rmse_avg_m: f.rmse_time_avg.get("pos_m").copied().flatten(),
                anees: f.consistency.anees,
                min_within_3sigma: f
                    .within_3sigma_frac
                    .values()
                    .flatten()
                    .copied()
                    .reduce(f64::min),
                diverged: Some(f.diverged),
                us_per_step: Some(f.us_per_step),
                min_delta_scaled: min_delta,
                delivery,
            });
        }
        reports.push((
            cell.label.clone(),
            entrynav::sim::monte_carlo::shard::scenario_fingerprint(&scenario),
            report,
        ));
        // Each finished cell is in the report at once, so an interrupted grid keeps them.
        write_outputs(&grid, out_dir, &rows, &reports, (cells.len(), html))?;
    }
    write_outputs(&grid, out_dir, &rows, &reports, (cells.len(), html))?;
    println!(
        "grid {}: {} cells, report in {}",
        grid.name,
        cells.len(),
        out_dir.display()
    );
    Ok(())
}
