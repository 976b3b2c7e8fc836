//! Stacked density profiles (a Mars-GRAM Monte Carlo set) and the datum of their heights.
//!
//! Mars-GRAM Monte Carlo output stacks n profiles in one file: the height column (`Var_X`)
//! restarts (e.g. from −5 km) at each. [`parse_profiles`] splits the rows where the height order
//! breaks ([`super::parse`] describes the header and columns) and places every profile on our
//! reference sphere:
//!
//! * with a radius column (`Radius`, km, planet-centred): altitude = radius − sphere radius;
//! * otherwise by the stated [`Datum`]: `sphere` takes heights as altitudes above our sphere,
//!   `areoid` adds the approximate areoid radius at the entry latitude ([`areoid_radius_m`])
//!   minus the sphere radius. Neither given: `sphere` is assumed and
//!   [`ProfileSet::assumption_warning`] says so (the CLI prints it).
//!
//! An explicitly stated datum overrides a radius column. At most [`MAX_PROFILES`] profiles.

use std::sync::Arc;

use serde::{Deserialize, Serialize};

use super::columns::TableColumns;
use super::error::AtmosphereError;
use super::model::AtmosphereModel;
use super::parse::{TableFormat, read_table, split_profiles};
use super::tabulated::{MIN_TABLE_POINTS, Tabulated};

/// Most stacked profiles read from one file; more is an error.
pub const MAX_PROFILES: usize = 10_000;

/// Areoid radius at the equator (km) of the approximation [`areoid_radius_m`].
pub const AREOID_EQUATOR_KM: f64 = 3395.5;
/// Equator-to-pole drop (km) of the approximation [`areoid_radius_m`].
pub const AREOID_POLAR_DROP_KM: f64 = 17.32;

/// Approximate radius (m) of the Mars areoid at geocentric latitude `latitude_rad`:
/// `R(φ) = 3395.5 km − 17.32 km · sin²φ`, an ellipsoid of revolution through 3395.5 km at 0°N
/// and 3378.7 km at 80°N (the Mars-GRAM values of issue 15).
///
/// Accuracy: the real (MOLA) areoid also varies with longitude and is not symmetric north-south;
/// expect errors of the order of 1–2 km (largest around Tharsis), i.e. 10–25 % in density at a
/// 7–10 km scale height. A file with a `Radius` column avoids the approximation.
pub fn areoid_radius_m(latitude_rad: f64) -> f64 {
    let s = latitude_rad.sin();
    (AREOID_EQUATOR_KM - AREOID_POLAR_DROP_KM * s * s) * 1e3
}

/// What the height column of a table is measured from, when it has no radius column.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "lowercase")]
pub enum Datum {
    /// Heights are altitudes above our reference sphere.
    Sphere,
    /// Heights are above the local areoid (Mars-GRAM's `HgtMOLA`, `Var_X`), approximated by
    /// [`areoid_radius_m`] at the entry latitude.
    Areoid,
}

/// How the rows of a set were placed on the reference sphere.
#[derive(Debug, Clone, PartialEq)]
pub enum HeightReference {
    /// By the radius column of this name.
    Radius(String),
    /// Heights taken as altitudes above the sphere; `assumed` when no datum was stated.
    Sphere {
        /// No datum was given and the table has no radius column.
        assumed: bool,
    },
    /// Heights above the approximate areoid at this latitude.
    Areoid {
        /// Entry latitude (deg) where the areoid radius was taken.
        latitude_deg: f64,
        /// The areoid radius used (km).
        radius_km: f64,
    },
}

impl std::fmt::Display for HeightReference {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            HeightReference::Radius(c) => {
                write!(f, "radius column {c} (altitude = radius − sphere radius)")
            }
            HeightReference::Sphere { assumed: false } => {
                f.write_str("heights above the reference sphere")
            }
            HeightReference::Sphere { assumed: true } => f.write_str(
                "heights above the reference sphere (assumed: no datum given, no radius column)",
            ),
            HeightReference::Areoid {
                latitude_deg,
                radius_km,
            } => write!(
                f,
                "heights above the areoid, approximated as {radius_km:.3} km radius at latitude {latitude_deg:.3}°"
            ),
        }
    }
}

/// Where a table's heights are placed: the stated datum, our sphere radius, the entry latitude.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Placement {
    /// Stated datum (`None`: radius column if any, else sphere, assumed).
    pub datum: Option<Datum>,
    /// Radius of the reference sphere (m).
    pub sphere_radius_m: f64,
    /// Geocentric latitude of the entry interface (rad), for the areoid datum.
    pub latitude_rad: f64,
}

/// One profile of a set: its data lines and spline.
#[derive(Debug, Clone, PartialEq)]
pub struct Profile {
    /// First data line (1-based).
    pub first_line: usize,
    /// Last data line (1-based).
    pub last_line: usize,
    /// The profile, altitudes above the reference sphere.
    pub table: Tabulated,
}

/// A table file read as one or more stacked profiles.
#[derive(Debug, Clone, PartialEq)]
pub struct ProfileSet {
    /// Source (file) name.
    pub source_name: String,
    /// Header name of the height column used.
    pub height_column: String,
    /// Header name of the density column used.
    pub density_column: String,
    /// How heights were placed.
    pub reference: HeightReference,
    /// The profiles in file order (at least one).
    pub profiles: Vec<Profile>,
}

impl ProfileSet {
    /// A warning to show when the datum was assumed, `None` otherwise.
    pub fn assumption_warning(&self) -> Option<String> {
        matches!(self.reference, HeightReference::Sphere { assumed: true }).then(|| {
            format!(
                "{}: no radius column and no datum given; heights in {} are taken as altitudes above the {} reference sphere. Mars-GRAM heights are above the local areoid (up to ~18 km lower near the poles): state the datum (--atmosphere-datum sphere|areoid, or datum = \"...\" in the scenario)",
                self.source_name, self.height_column, "planet's"
            )
        })
    }
}

/// Read `text` as stacked profiles: header and columns as in [`super::parse`], a new profile
/// wherever the height order breaks, heights placed by `placement`. Every profile needs at least
/// [`MIN_TABLE_POINTS`] rows; errors name the source, the lines and the profile.
pub fn parse_profiles(
    text: &str,
    source_name: &str,
    format: TableFormat,
    columns: &TableColumns,
    placement: &Placement,
) -> Result<ProfileSet, AtmosphereError> {
    let table = read_table(text, source_name, format, columns)?;
    let parts = split_profiles(&table.rows, source_name, columns.height_unit)?;
    if let Some(extra) = parts.get(MAX_PROFILES) {
        return Err(AtmosphereError::TooManyProfiles {
            source_name: source_name.to_string(),
            line: table.rows[extra.start].line,
            limit: MAX_PROFILES,
        });
    }
    if parts.len() <= 1 && table.rows.len() < MIN_TABLE_POINTS {
        return Err(AtmosphereError::TooFewRows {
            source_name: source_name.to_string(),
            found: table.rows.len(),
            required: MIN_TABLE_POINTS,
        });
    }
    let r_sphere = placement.sphere_radius_m;
    let reference = match (placement.datum, &table.radius_column) {
        (Some(Datum::Sphere), _) => HeightReference::Sphere { assumed: false },
        (Some(Datum::Areoid), _) => HeightReference::Areoid {
            latitude_deg: placement.latitude_rad.to_degrees(),
            radius_km: areoid_radius_m(placement.latitude_rad) / 1e3,
        },
        (None, Some(c)) => HeightReference::Radius(c.clone()),
        (None, None) => HeightReference::Sphere { assumed: true },
    };
    let offset = match reference {
        HeightReference::Areoid { radius_km, .. } => radius_km * 1e3 - r_sphere,
        _ => 0.0,
    };
    let mut profiles = Vec::with_capacity(parts.len());
    for (k, range) in parts.into_iter().enumerate() {
        let rows = &table.rows[range];
        let (first_line, last_line) = (rows[0].line, rows[rows.len() - 1].line);
        let bad = |problem: String| AtmosphereError::BadProfile {
            source_name: source_name.to_string(),
            profile: k,
            first_line,
            last_line,
            problem,
        };
        if rows.len() < MIN_TABLE_POINTS {
            return Err(bad(format!(
                "found {} data rows, at least {MIN_TABLE_POINTS} are needed",
                rows.len()
            )));
        }
        let alt: Vec<f64> = rows
            .iter()
            .map(|r| match (&reference, r.radius_m) {
                (HeightReference::Radius(_), Some(radius)) => radius - r_sphere,
                _ => r.height_m + offset,
            })
            .collect();
        let rho = rows.iter().map(|r| r.density).collect();
        let table = Tabulated::new(alt, rho).map_err(|e| bad(e.to_string()))?;
        profiles.push(Profile {
            first_line,
            last_line,
            table,
        });
    }
    Ok(ProfileSet {
        source_name: source_name.to_string(),
        height_column: table.height_column,
        density_column: table.density_column,
        reference,
        profiles,
    })
}

/// Which profile of a set each Monte Carlo run flies: profile `selected` for every run, or
/// **run k flies profile k mod n** (n = number of profiles). The rule depends only on the run
/// index, so threads and shards fly the same profiles.
#[derive(Debug, Clone, PartialEq)]
pub struct ProfileChoice {
    /// The profiles.
    pub set: Arc<ProfileSet>,
    /// One profile for every run, or `None` for the k mod n rule.
    pub selected: Option<usize>,
}

impl ProfileChoice {
    /// Check `selected` against the set (error naming the allowed range).
    pub fn new(set: ProfileSet, selected: Option<usize>) -> Result<ProfileChoice, AtmosphereError> {
        let count = set.profiles.len();
        if let Some(profile) = selected.filter(|&p| p >= count) {
            return Err(AtmosphereError::ProfileOutOfRange {
                source_name: set.source_name.clone(),
                profile,
                count,
                max: count.saturating_sub(1),
            });
        }
        Ok(ProfileChoice {
            set: Arc::new(set),
            selected,
        })
    }

    /// Number of profiles in the set.
    pub fn count(&self) -> usize {
        self.set.profiles.len()
    }

    /// Whether runs cycle through several profiles.
    pub fn is_cycling(&self) -> bool {
        self.selected.is_none() && self.count() > 1
    }

    /// Index of the profile run `run` flies.
    pub fn profile_for_run(&self, run: usize) -> usize {
        self.selected.unwrap_or(run % self.count().max(1))
    }

    /// The atmosphere of run `run`.
    pub fn model_for_run(&self, run: usize) -> AtmosphereModel {
        AtmosphereModel::Tabulated(self.set.profiles[self.profile_for_run(run)].table.clone())
    }

    /// What a report records about the truth atmosphere.
    pub fn provenance(&self) -> ProfileProvenance {
        let n = self.count();
        ProfileProvenance {
            file: self.set.source_name.clone(),
            profiles: n,
            profile: self.selected,
            rule: match self.selected {
                Some(k) => format!("every run flies profile {k} of {n}"),
                None => format!("run k flies profile k mod {n}"),
            },
            heights: self.set.reference.to_string(),
        }
    }
}

/// The truth atmosphere file of a study, as recorded in trade reports.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct ProfileProvenance {
    /// Source file.
    pub file: String,
    /// Number of profiles in the file.
    pub profiles: usize,
    /// The one profile flown (`--atmosphere-profile`), or `None` for the k mod n rule.
    pub profile: Option<usize>,
    /// The run → profile rule in words.
    pub rule: String,
    /// How heights were placed on the reference sphere.
    pub heights: String,
}
