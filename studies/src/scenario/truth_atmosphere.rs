//! A density table (CSV, Mars-GRAM output, a Mars-GRAM Monte Carlo set of stacked profiles) as
//! the truth mean atmosphere of a study (`trade --atmosphere-file`, `train-density --evaluate`),
//! and the checks shared with `atmosphere inspect`.

use crate::error::{StudyError, StudyResult};
use crate::scenario::input::ScenarioInput;
use entrynav::atmosphere::{
    AtmosphereConfig, AtmosphereError, Datum, Placement, TableColumns, TableFormat, parse_profiles,
};
use entrynav::scenario::{Scenario, ScenarioConfig};
use std::path::{Path, PathBuf};

/// The truth atmosphere file and how to read it.
#[derive(Clone, Debug, Default)]
pub struct TruthAtmosphere {
    /// The density table that becomes the truth mean atmosphere. With n stacked profiles, run k
    /// flies profile k mod n.
    pub file: Option<PathBuf>,
    /// Height column of the file (default: height, hgtkm, var_x, hgtmola, height_km, ...).
    pub height_column: Option<String>,
    /// Density column of the file, kg/m³ (default: denstot, density, rho, denavg, ...).
    pub density_column: Option<String>,
    /// What the file's heights are measured from when it has no Radius column.
    pub datum: Option<Datum>,
    /// Fly only profile K (0-based) of a file of stacked profiles, in every run.
    pub profile: Option<usize>,
    /// Keep the scenario's synthetic per-run perturbation on top of stacked profiles.
    pub perturb_profiles: bool,
}

impl TruthAtmosphere {
    /// Just a file, everything else default.
    pub fn file(path: impl Into<PathBuf>) -> Self {
        TruthAtmosphere {
            file: Some(path.into()),
            ..TruthAtmosphere::default()
        }
    }
}

impl TruthAtmosphere {
    /// `cfg` with `self.file` as its truth mean atmosphere (format from its header line, height
    /// unit from a unit-declaring header), without the per-run perturbation when asked
    /// (`no_perturbation`) or when the file holds several stacked profiles (unless
    /// `perturb_profiles`), validated. Parse errors name the file and line.
    pub fn apply(
        &self,
        mut cfg: ScenarioConfig,
        no_perturbation: bool,
    ) -> StudyResult<ScenarioConfig> {
        if let Some(path) = &self.file {
            replace_truth_atmosphere(&mut cfg, path, self)?;
        }
        if no_perturbation {
            cfg.truth.perturbation = None;
        }
        cfg.validate()?;
        Ok(cfg)
    }
}

impl ScenarioInput {
    /// This scenario with the truth atmosphere of `atmosphere` ([`TruthAtmosphere::apply`]).
    pub fn with_truth_atmosphere(
        mut self,
        atmosphere: &TruthAtmosphere,
        no_perturbation: bool,
    ) -> StudyResult<ScenarioInput> {
        self.config = atmosphere.apply(self.config, no_perturbation)?;
        if let Some(path) = &atmosphere.file {
            self.atmosphere_file = Some(path.clone());
        }
        Ok(self)
    }
}

fn replace_truth_atmosphere(
    cfg: &mut ScenarioConfig,
    path: &Path,
    a: &TruthAtmosphere,
) -> StudyResult<()> {
    let text = crate::input::read_text(path, "atmosphere_file")?;
    let format = TableFormat::detect(&text);
    let abs = std::fs::canonicalize(path).map_err(|e| {
        StudyError::Refused(format!(
            "cannot resolve atmosphere file {}: {e}",
            path.display()
        ))
    })?;
    let name = abs.display().to_string();
    let mut columns = TableColumns::named(
        a.height_column.as_deref(),
        a.density_column.as_deref(),
        None,
    );
    let placement = Placement {
        datum: a.datum,
        sphere_radius_m: cfg.planet.resolve().radius,
        latitude_rad: 0.0,
    };
    let parse = |c: &TableColumns| parse_profiles(&text, &name, format, c, &placement);
    // A header that declares its height unit (e.g. `Height(m)`) sets it.
    if let Err(AtmosphereError::HeightUnitMismatch { declared, .. }) = parse(&columns) {
        columns.height_unit = declared;
    }
    let set = parse(&columns).map_err(|e| match e {
        // A column the user named that the header lacks: name the option that asked for it.
        AtmosphereError::MissingColumn { role, .. } => {
            StudyError::Refused(format!("atmosphere_{role}_column: {e}"))
        }
        e => StudyError::Refused(e.to_string()),
    })?;
    let count = set.profiles.len();
    if let Some(p) = a.profile.filter(|&p| p >= count) {
        return Err(crate::options::OptionError::new(
            "atmosphere_profile",
            p,
            format!(
                "from 0 to {} (the profiles of {})",
                count - 1,
                path.display()
            ),
        )
        .into());
    }
    cfg.truth.atmosphere = AtmosphereConfig::Table {
        file: name,
        format,
        height_column: a.height_column.clone(),
        density_column: a.density_column.clone(),
        height_unit: Some(columns.height_unit),
        datum: a.datum,
        profile: a.profile,
    };
    if count > 1 && !a.perturb_profiles {
        cfg.truth.perturbation = None;
    }
    Ok(())
}

/// What a built scenario's truth table assumed about its heights, and its profiles: the warnings
/// and notes a front end shows (each without its `warning: ` / `note: ` prefix).
pub fn truth_table_notes(scenario: &Scenario) -> (Vec<String>, Vec<String>) {
    let (mut warnings, mut notes) = (Vec::new(), Vec::new());
    let Some(choice) = &scenario.truth_profiles else {
        return (warnings, notes);
    };
    if let Some(w) = choice.set.assumption_warning() {
        warnings.push(w.to_string());
    }
    if choice.count() > 1 {
        let p = choice.provenance();
        // `rule` already says which profile(s) the runs fly.
        let perturbed = if scenario.config.truth.perturbation.is_some() {
            "with"
        } else {
            "without"
        };
        notes.push(format!(
            "{} holds {} profiles: {} ({perturbed} the synthetic per-run perturbation)",
            p.file, p.profiles, p.rule
        ));
    }
    (warnings, notes)
}

/// Altitude range (m) of the scenario's nominal truth trajectory, flown in profile 0.
pub fn nominal_altitudes(scenario: &Scenario) -> StudyResult<(f64, f64)> {
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
pub fn check_profile_covers(scenario: &Scenario, file: &Path) -> StudyResult<()> {
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
        return Err(StudyError::Refused(format!(
            "{}: lines {}-{}: {which} covers {:.3}-{:.3} km but the {} trajectory flies between {:.3} and {:.3} km; give a profile spanning at least those altitudes",
            file.display(),
            p.first_line,
            p.last_line,
            lo / 1e3,
            hi / 1e3,
            scenario.config.name,
            h_min / 1e3,
            h_max / 1e3
        )));
    }
    Ok(())
}
