//! `entrynav guidance reference`: the reference trajectory `[guidance]` builds from the onboard
//! nominal entry (Mendeck & Craig, AIAA 2011-6639: the reference drag, altitude-rate and
//! range-to-go profiles against speed, and the gains F1 = ∂R/∂D, F2 = ∂R/∂ṙ, F3 = ∂R/∂(L/D)
//! from the adjoint sensitivities), printed as a summary and written as CSV / JSON.

use anyhow::{Context, Result, anyhow};
use clap::Args;
use entrynav::guidance::BuiltGuidance;
use entrynav_loader as load;
use serde_json::json;
use std::path::PathBuf;

/// Arguments of `entrynav guidance reference`.
#[derive(Args)]
pub struct ReferenceArgs {
    /// Built-in scenario name or path to a scenario TOML file (with a `[guidance]` section, or
    /// one given by --set).
    #[arg(long)]
    pub scenario: String,
    /// Override a scenario field: PATH=VALUE in TOML syntax (repeatable).
    #[arg(long = "set", value_name = "PATH=VALUE")]
    pub sets: Vec<String>,
    /// Write the tabulated reference as CSV (one row per point, speed decreasing).
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Write the summary and the table as JSON.
    #[arg(long)]
    pub json: Option<PathBuf>,
}

const COLUMNS: [&str; 12] = [
    "t_s",
    "speed_mps",
    "altitude_m",
    "fpa_deg",
    "downrange_m",
    "range_to_go_m",
    "drag_mps2",
    "rdot_mps",
    "f1_m_per_mps2",
    "f2_m_per_mps",
    "f3_m",
    "u_vertical_ld",
];

/// Run `entrynav guidance reference`.
pub fn run(args: &ReferenceArgs) -> Result<()> {
    if let Some(p) = &args.csv {
        crate::exit::check_output_file(p, "--csv")?;
    }
    if let Some(p) = &args.json {
        crate::exit::check_output_file(p, "--json")?;
    }
    let (cfg, dir) = load::resolve(&args.scenario, load::Base::CurrentDir)?.into_parts();
    let cfg = load::apply_overrides(cfg, &args.sets)?;
    let scenario = load::build(cfg, &dir)?;
    let built: BuiltGuidance = scenario
        .build_guidance()
        .ok_or_else(|| {
            crate::exit::Usage(format!(
                "scenario '{}' has no [guidance] section; add one (or --set 'guidance={{…}}')",
                scenario.config.name
            ))
        })?
        .with_context(|| format!("the reference of '{}'", scenario.config.name))?;
    let radius = scenario.planet.radius;
    let r = &built.reference;
    let rows: Vec<[f64; 12]> = r
        .points
        .iter()
        .map(|p| {
            [
                p.t,
                p.x[2],
                p.x[1] - radius,
                p.x[3].to_degrees(),
                p.x[0] * radius,
                p.range_to_go,
                p.drag,
                p.rdot,
                p.f1,
                p.f2,
                p.f3,
                p.x[4],
            ]
        })
        .collect();
    let last = rows
        .last()
        .ok_or_else(|| anyhow!("the reference of '{}' has no point", scenario.config.name))?;
    let (lat, lon) = (built.target.lat.to_degrees(), built.target.lon.to_degrees());
    let mut notes = Vec::new();
    if let Some(path) = &args.csv {
        crate::csv_file::write(path, |w| {
            w.write_record(COLUMNS)?;
            for row in &rows {
                w.write_record(row.iter().map(|v| format!("{v:.9e}")))?;
            }
            Ok(())
        })?;
        notes.push(format!("wrote {}", path.display()));
    }
    if let Some(path) = &args.json {
        let v = json!({
            "scenario": scenario.config.name,
            "reference_bank_deg": r.bank.to_degrees(),
            "vertical_lift_to_drag": r.vertical_ld,
            "downrange_to_trigger_m": r.total_range(radius),
            "target": {"lat_deg": lat, "lon_deg": lon},
            "columns": COLUMNS,
            "points": rows,
        });
        entrynav_studies::output::atomic_file::write(
            path,
            serde_json::to_string_pretty(&v)? + "\n",
        )?;
        notes.push(format!("wrote {}", path.display()));
    }
    println!(
        "reference of '{}': bank {:.2} deg (vertical L/D {:.4}), {} points over {:.1} s",
        scenario.config.name,
        r.bank.to_degrees(),
        r.vertical_ld,
        rows.len(),
        last[0]
    );
    println!(
        "  from {:.1} m/s at {:.0} m to the trigger at {:.1} m/s, {:.0} m; downrange {:.0} m",
        rows[0][1],
        rows[0][2],
        last[1],
        last[2],
        r.total_range(radius)
    );
    println!("  target latitude {lat:.4} deg, longitude {lon:.4} deg");
    for n in notes {
        println!("{n}");
    }
    Ok(())
}
