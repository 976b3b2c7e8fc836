//! Navigation filters.
//!
//! The module is layered:
//! * **algorithms** — the estimators themselves on plain vectors and matrices, independent of
//!   Mars entry: [`ekf`] (Joseph-form EKF), `ukf` (scaled unscented filter with the Schmidt
//!   consider form), `ci` (covariance intersection), `mmae` (multiple-model banks);
//! * **navigation filters** — adapters that wire an algorithm to the vehicle's onboard
//!   knowledge ([`Onboard`]: dynamics and measurement models, channels, beacons, tuning), in
//!   `nav`. A filter is built from an `Onboard` value alone and never sees the truth.
//!
//! This layer imports nothing from `scenario` or `sim`: the scenario builds the `Onboard` value,
//! the simulation engine drives the filters and judges them against the truth.
//!
//! Filters never panic on numerical trouble: every step returns a [`EstimationError`] that the
//! caller turns into a filter status.

pub mod adaptive;
pub mod chi_square;
pub mod ci;
mod ci_fast_weights;
mod ci_scaling;
mod ci_weight_problem;
mod ci_weights;
pub mod covariance;
pub mod ekf;
pub mod error;
pub mod gating;
pub mod linearization;
pub mod mmae;
pub mod model_probability;
pub mod nav;
pub mod onboard;
pub mod process_noise;
pub mod propagate;
pub mod spd;
pub mod ukf;
pub mod unscented;

pub use covariance::{check_covariance, symmetrize};
pub use error::EstimationError;
pub use onboard::{FilterRetune, FilterTuning, FusionCovariance, Onboard, OnboardChannel};
pub use process_noise::{AeroScaledNoise, MAX_AERO_FRACTION, MAX_DENSITY_SIGMA, ProcessNoiseModel};
