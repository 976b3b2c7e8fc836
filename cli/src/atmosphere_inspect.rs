//! `entrynav atmosphere inspect FILE`: what a density table holds and whether it fits a scenario.

use crate::atmosphere_file::{
    AtmosphereFileArgs, nominal_altitudes, report_truth_table, truth_atmosphere,
};
use crate::figures::write_line_plot as line_plot;
use anyhow::{Context, Result};
use clap::{Args, Subcommand};
use entrynav::atmosphere::{Atmosphere, Datum};
use entrynav_loader as load;
use entrynav_render::chart::Curve;
use std::path::PathBuf;

/// `entrynav atmosphere`.
#[derive(Subcommand)]
pub enum AtmosphereAction {
    /// Profiles, height and density ranges, datum and scenario coverage of a density table
    /// (CSV, Mars-GRAM output, a Mars-GRAM Monte Carlo set), with an optional SVG plot.
    Inspect(InspectArgs),
    /// Write the synthetic test set of truth atmospheres (0.1-3x the mean above 80 km, +-30 %
    /// below, seeded perturbation) as a Mars-GRAM Monte Carlo set file (docs/density.md).
    Generate(crate::atmosphere_generate::GenerateArgs),
}

/// Arguments of `entrynav atmosphere inspect`.
#[derive(Args)]
pub struct InspectArgs {
    /// The table file.
    pub file: PathBuf,
    /// Scenario whose nominal trajectory heights the profiles must cover, and whose onboard
    /// model is plotted.
    #[arg(long, default_value = "msl-airdata")]
    pub scenario: String,
    /// Height column (as `trade --atmosphere-height-column`).
    #[arg(long, value_name = "NAME")]
    pub atmosphere_height_column: Option<String>,
    /// Density column (as `trade --atmosphere-density-column`).
    #[arg(long, value_name = "NAME")]
    pub atmosphere_density_column: Option<String>,
    /// `sphere` or `areoid` (as `trade --atmosphere-datum`).
    #[arg(long, value_name = "sphere|areoid", value_parser = ["sphere", "areoid"])]
    pub atmosphere_datum: Option<String>,
    /// Write an SVG of the profiles' density (log scale) against height, with the scenario's
    /// onboard model.
    #[arg(long, value_name = "PATH")]
    pub svg: Option<PathBuf>,
}

/// Most profiles drawn one by one in the SVG; larger sets add their min/max envelope.
const PLOTTED_PROFILES: usize = 6;

/// Run the command.
pub fn run(action: &AtmosphereAction) -> Result<()> {
    let args = match action {
        AtmosphereAction::Inspect(args) => args,
        AtmosphereAction::Generate(args) => return crate::atmosphere_generate::run(args),
    };
    crate::preflight::check_output_files(&[(args.svg.as_deref(), "--svg")])?;
    entrynav_studies::input::check_file(&args.file, "FILE")?;
    let file_args = AtmosphereFileArgs {
        atmosphere_height_column: args.atmosphere_height_column.clone(),
        atmosphere_density_column: args.atmosphere_density_column.clone(),
        atmosphere_datum: args.atmosphere_datum.as_deref().map(|d| match d {
            "areoid" => Datum::Areoid,
            _ => Datum::Sphere,
        }),
        ..AtmosphereFileArgs::file(args.file.clone())
    };
    let (cfg, dir) = load::resolve(&args.scenario, load::Base::CurrentDir)?.into_parts();
    let cfg = truth_atmosphere(cfg, &file_args, true)?;
    let scenario = load::build(cfg, &dir)?;
    report_truth_table(&scenario);
    let choice = scenario
        .truth_profiles
        .as_ref()
        .context("the file did not become a table atmosphere")?;
    let set = &choice.set;
    let n = set.profiles.len();
    println!("file      {}", set.source_name);
    println!(
        "columns   height {}, density {} (kg/m³)",
        set.height_column, set.density_column
    );
    println!("datum     {}", set.reference);
    println!("profiles  {n}");
    let (h_min, h_max) = nominal_altitudes(&scenario)?;
    let mut covering = 0;
    for (k, p) in set.profiles.iter().enumerate() {
        let (lo, hi) = p.table.altitude_range();
        let rho = p.table.knot_densities();
        let (r_lo, r_hi) = rho
            .iter()
            .fold((f64::INFINITY, 0.0_f64), |(a, b), &r| (a.min(r), b.max(r)));
        let covers = p.table.covers(h_min, h_max);
        covering += usize::from(covers);
        if k < 20 || k + 1 == n {
            println!(
                "  profile {k:>4}: lines {}-{}, {} rows, altitude {:.3} to {:.3} km, density {r_lo:.4e} to {r_hi:.4e} kg/m³{}",
                p.first_line,
                p.last_line,
                p.table.num_knots(),
                lo / 1e3,
                hi / 1e3,
                if covers {
                    ""
                } else {
                    "  (does NOT cover the trajectory)"
                }
            );
        } else if k == 20 {
            println!("  ...");
        }
    }
    println!(
        "scenario  {}: nominal trajectory between {:.3} and {:.3} km; covered by {covering} of {n} profile(s)",
        scenario.config.name,
        h_min / 1e3,
        h_max / 1e3
    );
    let onboard = &scenario.onboard.model.atmosphere;
    println!(
        "onboard   {} model; profile / onboard density ratio:",
        onboard.kind()
    );
    for h_km in [0.0, 20.0, 40.0, 60.0, 80.0, 100.0, 120.0] {
        let h = h_km * 1e3;
        let ratios: Vec<f64> = set
            .profiles
            .iter()
            .filter(|p| p.table.covers(h, h))
            .map(|p| p.table.density(h) / onboard.density(h))
            .collect();
        if ratios.is_empty() {
            continue;
        }
        let (lo, hi) = ratios
            .iter()
            .fold((f64::INFINITY, 0.0_f64), |(a, b), &r| (a.min(r), b.max(r)));
        println!("  {h_km:>5.0} km: {lo:.3} to {hi:.3}");
    }
    if let Some(path) = &args.svg {
        plot(path, set, onboard, &scenario.config.name)?;
        println!("wrote {}", path.display());
    }
    Ok(())
}

fn plot(
    path: &std::path::Path,
    set: &entrynav::atmosphere::ProfileSet,
    onboard: &entrynav::atmosphere::AtmosphereModel,
    scenario: &str,
) -> Result<()> {
    if let Some(parent) = path.parent().filter(|p| !p.as_os_str().is_empty()) {
        std::fs::create_dir_all(parent)
            .with_context(|| format!("cannot create {}", parent.display()))?;
    }
    let n = set.profiles.len();
    let knots = |p: &entrynav::atmosphere::Profile| -> Vec<(f64, f64)> {
        p.table
            .altitudes_m()
            .iter()
            .zip(p.table.knot_densities())
            .map(|(h, r)| (h / 1e3, r))
            .collect()
    };
    let mut curves: Vec<Curve> = set
        .profiles
        .iter()
        .take(PLOTTED_PROFILES)
        .enumerate()
        .map(|(k, p)| Curve {
            name: format!("profile {k}"),
            points: knots(p),
            dashed: false,
            color: None,
        })
        .collect();
    let (lo, hi) = set
        .profiles
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| {
            let (l, h) = p.table.altitude_range();
            (a.min(l), b.max(h))
        });
    let grid: Vec<f64> = (0..=200)
        .map(|i| lo + (hi - lo) * i as f64 / 200.0)
        .collect();
    if n > PLOTTED_PROFILES {
        for (name, pick) in [("min", f64::min as fn(f64, f64) -> f64), ("max", f64::max)] {
            let points = grid
                .iter()
                .map(|&h| {
                    let v = set
                        .profiles
                        .iter()
                        .map(|p| p.table.density(h))
                        .reduce(pick)
                        .unwrap_or(f64::NAN);
                    (h / 1e3, v)
                })
                .collect();
            curves.push(Curve {
                name: format!("{name} over {n} profiles"),
                points,
                dashed: true,
                color: None,
            });
        }
    }
    curves.push(Curve {
        name: format!("onboard model ({scenario})"),
        points: grid
            .iter()
            .map(|&h| (h / 1e3, onboard.density(h)))
            .collect(),
        dashed: true,
        color: None,
    });
    line_plot(
        path,
        &format!("{} profile(s) of {}", n, file_name(&set.source_name)),
        "altitude above the reference sphere (km)",
        "density (kg/m³)",
        true,
        &curves,
    )
}

fn file_name(path: &str) -> String {
    std::path::Path::new(path)
        .file_name()
        .map(|f| f.to_string_lossy().into_owned())
        .unwrap_or_else(|| path.to_string())
}
