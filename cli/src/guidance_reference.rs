//! `entrynav guidance reference`: the command over the reference study
//! (`entrynav_studies::guidance::reference`): the reference trajectory `[guidance]` builds from
//! the onboard nominal entry and its adjoint gains, printed as a summary and written as CSV / JSON.

use anyhow::Result;
use clap::Args;
use entrynav_studies::ScenarioInput;
use entrynav_studies::guidance::run_reference;
use std::path::PathBuf;

/// Arguments of `entrynav guidance reference`.
#[derive(Args)]
pub struct ReferenceArgs {
    /// Built-in scenario name or path to a scenario TOML file (with a `[guidance]` section, or
    /// one given by --set).
    #[arg(long)]
    pub scenario: String,
    /// The `--set` overrides.
    #[command(flatten)]
    pub overrides: crate::args::SetArgs,
    /// Write the tabulated reference as CSV (one row per point, speed decreasing).
    #[arg(long)]
    pub csv: Option<PathBuf>,
    /// Write the summary and the table as JSON.
    #[arg(long)]
    pub json: Option<PathBuf>,
}

/// Run `entrynav guidance reference`.
pub fn run(args: &ReferenceArgs) -> Result<()> {
    if let Some(p) = &args.csv {
        crate::preflight::check_output_file(p, "--csv")?;
    }
    if let Some(p) = &args.json {
        crate::preflight::check_output_file(p, "--json")?;
    }
    let scenario = ScenarioInput::resolve(&args.scenario, &args.overrides.sets)?.build()?;
    let r = run_reference(&scenario)?;
    let mut notes = Vec::new();
    if let Some(path) = &args.csv {
        crate::csv_file::write(path, |w| Ok(r.write_csv(w)?))?;
        notes.push(format!("wrote {}", path.display()));
    }
    if let Some(path) = &args.json {
        let text = serde_json::to_string_pretty(&r.to_json())? + "\n";
        entrynav_studies::output::atomic_file::write(path, text)?;
        notes.push(format!("wrote {}", path.display()));
    }
    let Some((first, last)) = r.ends() else {
        return Ok(());
    };
    println!(
        "reference of '{}': bank {:.2} deg (vertical L/D {:.4}), {} points over {:.1} s",
        r.scenario,
        r.bank_deg,
        r.vertical_ld,
        r.rows.len(),
        last[0]
    );
    println!(
        "  from {:.1} m/s at {:.0} m to the trigger at {:.1} m/s, {:.0} m; downrange {:.0} m",
        first[1], first[2], last[1], last[2], r.downrange_to_trigger_m
    );
    let (lat, lon) = r.target_deg;
    println!("  target latitude {lat:.4} deg, longitude {lon:.4} deg");
    for n in notes {
        println!("{n}");
    }
    Ok(())
}
