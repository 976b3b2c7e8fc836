//! A grid's cells: every scenario of the grid file with every combination of its variations
//! (beacon sets from other files, the first N beacons, a fault of the last beacon, the scale of
//! the truth density perturbation and of every sensor noise), each a validated scenario.

use crate::error::{StudyError, StudyResult};
use crate::grid::file::GridFile;
use entrynav::atmosphere::PerturbationConfig;
use entrynav::scenario::ScenarioConfig;
use entrynav_loader as load;
use std::path::{Path, PathBuf};

/// One cell of a grid: a scenario with one value of each variation.
#[derive(Debug, Clone)]
pub struct GridCell {
    /// `c00`, `c01`, … in expansion order.
    pub label: String,
    /// The variation values (`2 beacons, fault after 200 s`), `nominal` for none.
    pub variation: String,
    /// The cell's scenario, validated.
    pub config: ScenarioConfig,
    /// The folder its relative file names resolve against.
    pub dir: PathBuf,
}

/// Scale every sensor noise of `cfg` (and the filters' assumed IMU noise) by `k`.
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

/// The cells of `grid` (whose relative file names resolve against `grid_dir`), in order:
/// scenario, then beacon file, beacon count, fault, perturbation scale, noise scale.
pub fn expand(grid: &GridFile, grid_dir: &Path) -> StudyResult<Vec<GridCell>> {
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
                                    return Err(StudyError::Refused(format!(
                                        "variations.beacons = {n}: scenario {} has only {} beacons",
                                        cfg.name,
                                        cfg.beacons.len()
                                    )));
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
                                        return Err(StudyError::Refused(format!(
                                            "variations.beacon_fault: scenario {} has no beacon to fail",
                                            cfg.name
                                        )));
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
                            cells.push(GridCell {
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
