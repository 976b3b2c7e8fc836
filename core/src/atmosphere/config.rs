//! Scenario-file description of an atmosphere (TOML via serde) and its conversion to a model.
//!
//! Units at this boundary are km and kg/m³ as the field names say; everything built is SI.

use serde::{Deserialize, Serialize};

use super::columns::{HeightUnit, TableColumns};
use super::cospar::Cospar;
use super::error::{AtmosphereError, check_closed, check_open, field_path};
use super::exponential::Exponential;
use super::mars_mean::mars_mean_profile;
use super::model::AtmosphereModel;
use super::model::Perturbed;
use super::parse::TableFormat;
use super::perturbation_spec::{Envelope, PerturbationSpec};
use super::profiles::{Datum, Placement, ProfileChoice, parse_profiles};
use crate::files::FileLoader;
use crate::planet::Planet;

/// An atmosphere as written in a scenario file, selected by the `model` key.
///
/// ```toml
/// model = "exponential"   # or "cospar", "table", "mars-mean"
/// rho_ref_kgm3 = 2e-4
/// ref_radius_km = 3437.2
/// scale_height_km = 7.5
/// ```
/// Unknown keys are rejected.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "model", rename_all = "kebab-case", deny_unknown_fields)]
pub enum AtmosphereConfig {
    /// Exponential model, seed 000 eq. 3 / seed 001 eq. 16 in radius form (seeds 000/002/003:
    /// 2e-4 kg/m³, 3437.2 km, 7.5 km).
    Exponential {
        /// ρ0 at the reference radius (kg/m³).
        rho_ref_kgm3: f64,
        /// Reference radius r0 (km) (a radius, not an altitude).
        ref_radius_km: f64,
        /// Scale height hs (km).
        scale_height_km: f64,
    },
    /// Simplified COSPAR model, seed 001 eq. 17, with user-supplied coefficients.
    Cospar {
        /// ρ0 (kg/m³).
        rho0_kgm3: f64,
        /// Reference altitude h0 = r0 − R (km).
        ref_altitude_km: f64,
        /// β (1/km).
        beta_per_km: f64,
        /// γ (dimensionless).
        gamma: f64,
        /// ω (rad/km).
        omega_per_km: f64,
        /// δ (dimensionless).
        delta: f64,
    },
    /// A density table read by the caller-supplied loader and splined in ln ρ.
    Table {
        /// File name passed to the loader.
        file: String,
        /// `csv` or `mars-gram`.
        format: TableFormat,
        /// Height column name (default `height`, with aliases; see [`TableColumns`]).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        height_column: Option<String>,
        /// Density column name in kg/m³ (default `denstot`, with aliases).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        density_column: Option<String>,
        /// `km` (default) or `m`.
        #[serde(default, skip_serializing_if = "Option::is_none")]
        height_unit: Option<HeightUnit>,
        /// `sphere` or `areoid`: what heights are measured from when the file has no `Radius`
        /// column (see [`super::profiles`]); unset: the radius column, else `sphere` (assumed).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        datum: Option<Datum>,
        /// Fly only this 0-based profile of a file of stacked profiles; unset: run k flies
        /// profile k mod n ([`ProfileChoice`]).
        #[serde(default, skip_serializing_if = "Option::is_none")]
        profile: Option<usize>,
    },
    /// The built-in non-exponential mean profile ([`mars_mean_profile`]).
    ///
    /// Written as an empty struct variant on purpose: serde lets a *unit* variant of an
    /// internally tagged enum accept arbitrary extra keys, an empty struct variant rejects them.
    MarsMean {},
}

impl AtmosphereConfig {
    /// ρ0 (kg/m³) of an exponential model (the density a filter may augment as a state, seed 000),
    /// `None` for every other model.
    pub fn reference_density(&self) -> Option<f64> {
        match self {
            AtmosphereConfig::Exponential { rho_ref_kgm3, .. } => Some(*rho_ref_kgm3),
            _ => None,
        }
    }

    /// Check physical ranges; errors name `field_prefix.field`, the value and the allowed range.
    pub fn validate(&self, field_prefix: &str) -> Result<(), AtmosphereError> {
        let f = |name: &str| field_path(field_prefix, name);
        match self {
            AtmosphereConfig::Exponential {
                rho_ref_kgm3,
                ref_radius_km,
                scale_height_km,
            } => {
                check_open(&f("rho_ref_kgm3"), *rho_ref_kgm3, 0.0, 1.0)?;
                check_open(&f("ref_radius_km"), *ref_radius_km, 0.0, 1e6)?;
                check_open(&f("scale_height_km"), *scale_height_km, 0.0, 1000.0)?;
            }
            AtmosphereConfig::Cospar {
                rho0_kgm3,
                ref_altitude_km,
                beta_per_km,
                gamma,
                omega_per_km,
                delta,
            } => {
                check_open(&f("rho0_kgm3"), *rho0_kgm3, 0.0, 1.0)?;
                check_closed(&f("ref_altitude_km"), *ref_altitude_km, -100.0, 1000.0)?;
                check_open(&f("beta_per_km"), *beta_per_km, 0.0, 10.0)?;
                check_open(&f("gamma"), *gamma, -50.0, 50.0)?;
                check_closed(&f("omega_per_km"), *omega_per_km, 0.0, 10.0)?;
                check_open(&f("delta"), *delta, -50.0, 50.0)?;
            }
            AtmosphereConfig::Table {
                file,
                height_column,
                density_column,
                ..
            } => {
                if file.trim().is_empty() {
                    return Err(AtmosphereError::InvalidField {
                        field: f("file"),
                        problem: "must name a table file".to_string(),
                    });
                }
                for (name, col) in [
                    ("height_column", height_column),
                    ("density_column", density_column),
                ] {
                    if col.as_deref().is_some_and(|c| c.trim().is_empty()) {
                        return Err(AtmosphereError::InvalidField {
                            field: f(name),
                            problem: "must not be empty".to_string(),
                        });
                    }
                }
            }
            AtmosphereConfig::MarsMean {} => {}
        }
        Ok(())
    }

    /// Build the model. `load(file)` returns a table file's text (the CLI reads files; the core
    /// does no I/O); its `Err` becomes [`AtmosphereError::LoadFailed`] naming the file, and parse
    /// errors name the file as their source. The configuration is validated first (field prefix
    /// `atmosphere`); an exponential reference radius must lie within R − 100 km … R + 1000 km.
    /// A table of stacked profiles gives its selected profile, or profile 0; an areoid datum is
    /// taken at the equator (use [`AtmosphereConfig::build_at`] to give the entry latitude).
    pub fn build(
        &self,
        planet: &Planet,
        load: &FileLoader<'_>,
    ) -> Result<AtmosphereModel, AtmosphereError> {
        self.build_at(planet, 0.0, load).map(|(model, _)| model)
    }

    /// As [`AtmosphereConfig::build`], with the entry latitude (rad) for an areoid datum, and
    /// for a table also its profiles and which run flies which ([`ProfileChoice`]).
    pub fn build_at(
        &self,
        planet: &Planet,
        latitude_rad: f64,
        load: &FileLoader<'_>,
    ) -> Result<(AtmosphereModel, Option<ProfileChoice>), AtmosphereError> {
        self.validate("atmosphere")?;
        let model = match self {
            AtmosphereConfig::Exponential {
                rho_ref_kgm3,
                ref_radius_km,
                scale_height_km,
            } => {
                let r_km = planet.radius / 1e3;
                let h_ref_km = ref_radius_km - r_km;
                if !(-100.0..=1000.0).contains(&h_ref_km) {
                    return Err(AtmosphereError::out_of_range(
                        "atmosphere.ref_radius_km",
                        *ref_radius_km,
                        format!(
                            "must be between {} and {} km (planet radius {r_km} km − 100 km … + 1000 km; it is a radius, not an altitude)",
                            r_km - 100.0,
                            r_km + 1000.0
                        ),
                    ));
                }
                AtmosphereModel::Exponential(Exponential::from_reference_radius(
                    *rho_ref_kgm3,
                    ref_radius_km * 1e3,
                    scale_height_km * 1e3,
                    planet.radius,
                )?)
            }
            AtmosphereConfig::Cospar {
                rho0_kgm3,
                ref_altitude_km,
                beta_per_km,
                gamma,
                omega_per_km,
                delta,
            } => {
                let c = Cospar {
                    rho0: *rho0_kgm3,
                    h0: ref_altitude_km * 1e3,
                    beta: beta_per_km * 1e-3,
                    gamma: *gamma,
                    omega: omega_per_km * 1e-3,
                    delta: *delta,
                };
                c.validate()?;
                AtmosphereModel::Cospar(c)
            }
            AtmosphereConfig::Table {
                file,
                format,
                height_column,
                density_column,
                height_unit,
                datum,
                profile,
            } => {
                let text = load(file).map_err(|source| AtmosphereError::LoadFailed {
                    file: file.clone(),
                    source,
                })?;
                let columns = TableColumns::named(
                    height_column.as_deref(),
                    density_column.as_deref(),
                    *height_unit,
                );
                let placement = Placement {
                    datum: *datum,
                    sphere_radius_m: planet.radius,
                    latitude_rad,
                };
                let set = parse_profiles(&text, file, *format, &columns, &placement)?;
                let choice = ProfileChoice::new(set, *profile)?;
                return Ok((choice.model_for_run(0), Some(choice)));
            }
            AtmosphereConfig::MarsMean {} => AtmosphereModel::Tabulated(mars_mean_profile()),
        };
        Ok((model, None))
    }
}

fn default_scale() -> f64 {
    1.0
}
fn default_correlation_km() -> f64 {
    8.0
}
fn default_grid_step_km() -> f64 {
    1.0
}

/// Perturbation settings of a scenario (docs/density.md; seed 001 in docs/references.md); every key is optional.
///
/// ```toml
/// scale = 1.0            # multiplier of the envelope, 0 = unperturbed mean
/// correlation_km = 8.0   # correlation length L of the Gauss-Markov process
/// grid_step_km = 1.0     # AR(1) grid spacing
/// envelope = [[0, 0.02], [40, 0.05], [60, 0.085], [80, 0.175], [100, 0.30]]  # [km, 1σ fraction]
/// ```
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct PerturbationConfig {
    /// Multiplier of the envelope (default 1).
    #[serde(default = "default_scale")]
    pub scale: f64,
    /// Correlation length (km) (default 8).
    #[serde(default = "default_correlation_km")]
    pub correlation_km: f64,
    /// AR(1) grid spacing (km) (default 1).
    #[serde(default = "default_grid_step_km")]
    pub grid_step_km: f64,
    /// `[altitude_km, sigma_fraction]` points; default ([`Envelope::default`]): 0 km 2 %,
    /// 40 km 5 %, 60 km 8.5 %, 80 km 17.5 %, 100–150 km 30 %.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub envelope: Option<Vec<[f64; 2]>>,
}

impl Default for PerturbationConfig {
    fn default() -> Self {
        PerturbationConfig {
            scale: default_scale(),
            correlation_km: default_correlation_km(),
            grid_step_km: default_grid_step_km(),
            envelope: None,
        }
    }
}

impl PerturbationConfig {
    /// Check ranges (scale in [0, 10], correlation in (0, 10000) km, grid step in (0, 150] km,
    /// envelope altitudes in [−100, 10000] km strictly increasing, σ in [0, 10]); errors name
    /// `field_prefix.field`.
    pub fn validate(&self, field_prefix: &str) -> Result<(), AtmosphereError> {
        self.try_to_spec(field_prefix).map(|_| ())
    }

    /// Convert to an SI [`PerturbationSpec`] (grid 0-150 km) without checking.
    ///
    /// Call [`PerturbationConfig::validate`] first (scenario validation does). Invalid values are
    /// carried into the spec unchanged; [`Perturbed::sample`] then returns the unperturbed mean and
    /// [`Perturbed::try_sample`] reports the problem.
    pub fn to_spec(&self) -> PerturbationSpec {
        let envelope = match &self.envelope {
            None => Envelope::default(),
            Some(points) => {
                Envelope::from_points_unchecked(points.iter().map(|p| (p[0] * 1e3, p[1])).collect())
            }
        };
        PerturbationSpec {
            envelope,
            correlation_length_m: self.correlation_km * 1e3,
            grid_step_m: self.grid_step_km * 1e3,
            scale: self.scale,
            ..PerturbationSpec::default()
        }
    }

    /// Validate and convert to an SI [`PerturbationSpec`] (grid 0-150 km).
    pub fn try_to_spec(&self, field_prefix: &str) -> Result<PerturbationSpec, AtmosphereError> {
        let f = |name: &str| field_path(field_prefix, name);
        check_closed(&f("scale"), self.scale, 0.0, 10.0)?;
        check_open(&f("correlation_km"), self.correlation_km, 0.0, 1e4)?;
        if !(self.grid_step_km.is_finite() && self.grid_step_km > 0.0 && self.grid_step_km <= 150.0)
        {
            return Err(AtmosphereError::out_of_range(
                f("grid_step_km"),
                self.grid_step_km,
                "must be > 0 and <= 150",
            ));
        }
        let envelope = match &self.envelope {
            None => Envelope::default(),
            Some(points) => {
                if points.is_empty() {
                    return Err(AtmosphereError::InvalidField {
                        field: f("envelope"),
                        problem: "needs at least one [altitude_km, sigma] point".to_string(),
                    });
                }
                for (i, p) in points.iter().enumerate() {
                    check_closed(&f(&format!("envelope[{i}][0]")), p[0], -100.0, 1e4)?;
                    check_closed(&f(&format!("envelope[{i}][1]")), p[1], 0.0, 10.0)?;
                    if i > 0 && p[0] <= points[i - 1][0] {
                        return Err(AtmosphereError::InvalidField {
                            field: f(&format!("envelope[{i}]")),
                            problem: format!(
                                "altitude {} km does not increase (previous point is at {} km)",
                                p[0],
                                points[i - 1][0]
                            ),
                        });
                    }
                }
                Envelope::new(points.iter().map(|p| (p[0] * 1e3, p[1])).collect())?
            }
        };
        let spec = PerturbationSpec {
            envelope,
            correlation_length_m: self.correlation_km * 1e3,
            grid_step_m: self.grid_step_km * 1e3,
            scale: self.scale,
            ..PerturbationSpec::default()
        };
        spec.validate()?;
        Ok(spec)
    }

    /// Perturb `mean` with one reproducible realisation drawn from `seed`.
    pub fn apply(
        &self,
        mean: AtmosphereModel,
        seed: u64,
        field_prefix: &str,
    ) -> Result<AtmosphereModel, AtmosphereError> {
        let spec = self.try_to_spec(field_prefix)?;
        Ok(Perturbed::from_seed(mean, &spec, seed)?.into())
    }
}
