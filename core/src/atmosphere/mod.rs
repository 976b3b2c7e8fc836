//! Atmosphere models behind one trait.
//!
//! Every model maps geometric altitude above the reference sphere (`r − R`, metres) to density
//! (kg/m³) and is generic over [`Real`](crate::math::Real) so that dynamics and measurement Jacobians can be taken
//! through it by forward-mode AD.
//!
//! | model | source | type |
//! |---|---|---|
//! | exponential | seed 000 eq. 3, seed 001 eq. 16 | [`Exponential`] |
//! | simplified COSPAR | seed 001 eq. 17 | [`Cospar`] |
//! | ln ρ cubic-spline table (Mars-GRAM / CSV files) | seed 001 §V | [`Tabulated`], [`parse_csv`], [`parse_mars_gram`] |
//! | stacked Mars-GRAM Monte Carlo profiles, height datum | ours (issue 15) | [`ProfileSet`], [`parse_profiles`], [`ProfileChoice`] |
//! | built-in non-exponential mean profile | ours (docs/density.md) | [`mars_mean_profile`] |
//! | perturbed profile generator | ours (docs/density.md) | [`Perturbed`] |
//! | synthetic test set (scaled, perturbed means; GRAM text) | ours (issue 15) | [`generate_synthetic_set`] |
//!
//! [`AtmosphereModel`] gathers them for scenario-driven code and [`AtmosphereConfig`] /
//! [`PerturbationConfig`] describe them in scenario files. All failures are [`AtmosphereError`].

pub mod columns;
pub mod config;
pub mod cospar;
pub mod density_model;
pub mod error;
pub mod exponential;
pub mod mars_mean;
pub mod model;
pub mod parse;
pub mod perturbation_spec;
pub mod profiles;
pub mod synthetic_case;
pub mod synthetic_set;
mod table_header;
pub mod tabulated;

pub use columns::{DENSITY_ALIASES, HEIGHT_ALIASES, HeightUnit, RADIUS_ALIASES, TableColumns};
pub use config::{AtmosphereConfig, PerturbationConfig};
pub use cospar::Cospar;
pub use density_model::Atmosphere;
pub use error::AtmosphereError;
pub use exponential::{Exponential, exponential_density};
pub use mars_mean::{
    MARS_MEAN_GAS_CONSTANT, MARS_MEAN_KNEE_WIDTH_M, MARS_MEAN_SURFACE_PRESSURE_PA,
    MARS_MEAN_TEMPERATURE_KNOTS, MARS_MEAN_TOP_M, mars_mean_profile, mars_mean_temperature,
};
pub use model::{AtmosphereModel, Perturbed};
pub use parse::{MAX_TABLE_ROWS, TableFormat, parse_csv, parse_mars_gram};
pub use perturbation_spec::{Envelope, PerturbationSpec};
pub use profiles::{
    Datum, HeightReference, MAX_PROFILES, Placement, Profile, ProfileChoice, ProfileProvenance,
    ProfileSet, areoid_radius_m, parse_profiles,
};
pub use synthetic_case::SyntheticCase;
pub use synthetic_set::{
    SyntheticProfile, SyntheticSetSpec, generate_synthetic_set, synthetic_set_gram_text,
};
pub use tabulated::{MIN_TABLE_POINTS, Tabulated};
