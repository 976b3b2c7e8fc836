//! `--atmosphere-file` and its companions: the flags of a density table (CSV, Mars-GRAM output, a
//! Mars-GRAM Monte Carlo set of stacked profiles) as the truth mean atmosphere of `trade` and
//! `train-density --evaluate`; the study layer's `TruthAtmosphere` does the work.

use anyhow::Result;
use clap::Args;
use entrynav::atmosphere::Datum;
use entrynav::scenario::{Scenario, ScenarioConfig};
use entrynav_studies::scenario::truth_atmosphere::{TruthAtmosphere, truth_table_notes};
pub(crate) use entrynav_studies::scenario::truth_atmosphere::{
    check_profile_covers, nominal_altitudes,
};
use std::path::PathBuf;

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

impl AtmosphereFileArgs {
    /// The study layer's truth atmosphere of these flags.
    pub fn to_study(&self) -> TruthAtmosphere {
        TruthAtmosphere {
            file: self.atmosphere_file.clone(),
            height_column: self.atmosphere_height_column.clone(),
            density_column: self.atmosphere_density_column.clone(),
            datum: self.atmosphere_datum,
            profile: self.atmosphere_profile,
            perturb_profiles: self.perturb_profiles,
        }
    }
}

/// `cfg` with the truth atmosphere of `args` ([`TruthAtmosphere::apply`]).
pub(crate) fn truth_atmosphere(
    cfg: ScenarioConfig,
    args: &AtmosphereFileArgs,
    no_perturbation: bool,
) -> Result<ScenarioConfig> {
    Ok(args.to_study().apply(cfg, no_perturbation)?)
}

/// Print what a built scenario's truth table assumed about its heights, and its profiles.
pub(crate) fn report_truth_table(scenario: &Scenario) {
    let (warnings, notes) = truth_table_notes(scenario);
    for w in warnings {
        eprintln!("warning: {w}");
    }
    for n in notes {
        eprintln!("note: {n}");
    }
}
