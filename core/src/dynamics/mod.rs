//! Entry dynamics: spherical 3-DOF (with or without planet rotation) and Cartesian inertial.
//!
//! [`EntryModel`] wraps one of the right-hand sides with a vehicle, an atmosphere and an optional
//! list of *augmented states* appended after the six kinematic states: constants the filters of
//! seeds 000 (§2.3.1) and 001 (eq. 34) estimate (ρ0, L/D, C_D S/m), seed 003's density bias Δ
//! (eq. 6), and accelerometer biases (random constants, or first-order Gauss–Markov processes
//! ḃ = −b/τ). Jacobians are exact, by forward-mode AD through the same generic code
//! ([`EntryModel::jacobian`]).

pub mod aero;
pub mod augmented_param;
pub mod cartesian;
pub mod entry_model;
pub mod integrator;
pub mod kind;
pub mod noise_map;
pub mod spherical;

pub use augmented_param::AugmentedParam;
pub use cartesian::cartesian_rhs;
pub use entry_model::{EntryModel, Vehicle};
pub use integrator::{rk4_integrate, rk4_step, rk4_step_generic};
pub use kind::DynamicsKind;
pub use noise_map::AeroNoiseMap;
pub use spherical::spherical_rhs;
