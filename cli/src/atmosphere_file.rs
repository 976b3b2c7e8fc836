//! `--atmosphere-file` and its companions: a density table (CSV, Mars-GRAM output, a Mars-GRAM
//! Monte Carlo set of stacked profiles) as the truth mean atmosphere of `trade` and
//! `train-density --evaluate`, and the checks shared with `atmosphere inspect`.

use anyhow::{Context, Result};
use clap::Args;
use entrynav::atmosphere::{
    AtmosphereConfig, AtmosphereError, Datum, Placement, TableColumns, TableFormat, parse_profiles,
};
use entrynav::scenario::{Scenario, ScenarioConfig};
use std::path::{Path, PathBuf};

/// The truth atmosphere file and how to read it.
#[derive(Args, Clone, Debug, Default)]
pub struct AtmosphereFileArgs {
    /// Use this density table as the truth mean atmosphere: CSV, Mars-GRAM-style columns, or
    /// Mars-GRAM Monte Carlo output (`#` header line, stacked profiles). With n stacked
    /// profiles, run k flies profile k mod n (recorded in the trade JSON). A malformed,
    /// non-monotonic or non-positive profile, or one that does not cover the trajectory's
    /// altitudes, is refused.
    #[arg(long, value_name = "FILE")]
    pub atmosphere_file: Option<PathBuf>,
    /// Height column of the file (default: height, hgtkm, var_x, hgtmola, height_km, ...).
    #[arg(long, value_name = "NAME", requires = "atmosphere_file")]
    pub atmosphere_height_column: Option<String>,
    /// Density column of the file, kg/m³ (default: denstot, density, rho, denavg, ...).
    #[arg(long, value_name = "NAME", requires = "atmosphere_file")]
    pub atmosphere_density_column: Option<String>,
    /// What the file's heights are measured from when it has no Radius column: `sphere` (our
    /// reference sphere) or `areoid` (approximate areoid radius at the entry latitude). Not
    /// given: the Radius column, else sphere with a warning.
    #[arg(long, value_name = "sphere|areoid", value_parser = parse_datum, requires = "atmosphere_file")]
    pub atmosphere_datum: Option<Datum>,
    /// Fly only profile K (0-based) of a file of stacked profiles, in every run.
    #[arg(long, value_name = "K", requires = "atmosphere_file")]
    pub atmosphere_profile: Option<usize>,
    /// Keep the scenario's synthetic per-run perturbation on top of the profiles of a file of
    /// stacked profiles (off by default: the set's profiles are the dispersion).
    #[arg(long, requires = "atmosphere_file")]
    pub perturb_profiles: bool,
}

fn parse_datum(s: &str) -> Result<Datum, String> {
    match s {
        "sphere" => Ok(Datum::Sphere),
        "areoid" => Ok(Datum::Areoid),
        other => Err(format!("'{other}' is not a datum: use sphere or areoid")),
    }
}

impl AtmosphereFileArgs {
    /// Just a file, everything else default.
    pub fn file(path: impl Into<PathBuf>) -> Self {
        AtmosphereFileArgs {
            atmosphere_file: Some(path.into()),
            ..AtmosphereFileArgs::default()
        }
    }
}

/// Make `args.atmosphere_file` the truth mean atmosphere (format from its header line, height
/// unit from a unit-declaring header), drop the per-run perturbation when asked or when the
/// file holds several stacked profiles (unless `--perturb-profiles`). Parse errors name the
/// file and line.
pub(crate) fn truth_atmosphere(
    mut cfg: ScenarioConfig,
    args: &AtmosphereFileArgs,
    no_perturbation: bool,
) -> Result<ScenarioConfig> {
    if let Some(path) = &args.atmosphere_file {
        let text = entrynav_loader::read_text(path)
            .with_context(|| format!("cannot read atmosphere file {}", path.display()))?;
        let format = TableFormat::detect(&text);
        let abs = std::fs::canonicalize(path)
            .with_context(|| format!("cannot resolve atmosphere file {}", path.display()))?;
        let name = abs.display().to_string();
        let mut columns = TableColumns::named(
            args.atmosphere_height_column.as_deref(),
            args.atmosphere_density_column.as_deref(),
            None,
        );
        let placement = Placement {
            datum: args.atmosphere_datum,
            sphere_radius_m: cfg.planet.resolve().radius,
            latitude_rad: 0.0,
        };
        let parse = |c: &TableColumns| parse_profiles(&text, &name, format, c, &placement);
        // A header that declares its height unit (e.g. `Height(m)`) sets it.
        if let Err(AtmosphereError::HeightUnitMismatch { declared, .. }) = parse(&columns) {
            columns.height_unit = declared;
        }
        let set = parse(&columns)?;
        let count = set.profiles.len();
        cfg.truth.atmosphere = AtmosphereConfig::Table {
            file: name,
            format,
            height_column: args.atmosphere_height_column.clone(),
            density_column: args.atmosphere_density_column.clone(),
            height_unit: Some(columns.height_unit),
            datum: args.atmosphere_datum,
            profile: args.atmosphere_profile,
        };
        if count > 1 && !args.perturb_profiles {
            cfg.truth.perturbation = None;
        }
    }
    if no_perturbation {
        cfg.truth.perturbation = None;
    }
    cfg.validate()?;
    Ok(cfg)
}

/// Print what a built scenario's truth table assumed about its heights, and its profiles.
pub(crate) fn report_truth_table(scenario: &Scenario) {
    let Some(choice) = &scenario.truth_profiles else {
        return;
    };
    if let Some(w) = choice.set.assumption_warning() {
        eprintln!("warning: {w}");
    }
    if choice.count() > 1 {
        let p = choice.provenance();
        // `rule` already says which profile(s) the runs fly.
        let perturbed = if scenario.config.truth.perturbation.is_some() {
            "with"
        } else {
            "without"
        };
        eprintln!(
            "note: {} holds {} profiles: {} ({perturbed} the synthetic per-run perturbation)",
            p.file, p.profiles, p.rule
        );
    }
}

/// Altitude range (m) of the scenario's nominal truth trajectory, flown in profile 0.
pub(crate) fn nominal_altitudes(scenario: &Scenario) -> Result<(f64, f64)> {
    use rand::SeedableRng;
    let draw = scenario.nominal_truth();
    let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(0);
    let run = entrynav::sim::simulate_truth(scenario, &draw, &mut rng)?;
    Ok(run
        .samples
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), s| {
            (a.min(s.altitude), b.max(s.altitude))
        }))
}

/// Refuse a truth profile file any of whose profiles does not cover the altitudes of the
/// scenario's nominal trajectory, naming the file, the profile's data lines and both ranges.
pub(crate) fn check_profile_covers(scenario: &Scenario, file: &Path) -> Result<()> {
    let Some(choice) = &scenario.truth_profiles else {
        return Ok(());
    };
    let (h_min, h_max) = nominal_altitudes(scenario)?;
    let n = choice.count();
    for (k, p) in choice.set.profiles.iter().enumerate() {
        if choice.selected.is_some_and(|s| s != k) || p.table.covers(h_min, h_max) {
            continue;
        }
        let (lo, hi) = p.table.altitude_range();
        let which = if n > 1 {
            format!("profile {k} of {n}")
        } else {
            "the profile".to_string()
        };
        anyhow::bail!(
            "{}: lines {}-{}: {which} covers {:.3}-{:.3} km but the {} trajectory flies between {:.3} and {:.3} km; give a profile spanning at least those altitudes",
            file.display(),
            p.first_line,
            p.last_line,
            lo / 1e3,
            hi / 1e3,
            scenario.config.name,
            h_min / 1e3,
            h_max / 1e3
        );
    }
    Ok(())
}
