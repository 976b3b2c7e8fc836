//! Radio beacons: surface beacons fixed to the planet and orbiters in two-body motion.
//!
//! * [`SurfaceBeacon`] — fixed in the planet frame (seed 000 Table 2 surface beacons, seed 002
//!   §5.1 ground beacons), turning with the planet about +z.
//! * [`Orbiter`] — exact two-body (Kepler) motion, seed 003 eq. 8 / seed 002 §5.2, propagated
//!   analytically with universal variables; built from an inertial state, from Keplerian elements
//!   (seed 003 Table 3) or from the circular-orbit parametrisation of seed 002 eq. 55–56
//!   ([`elements`]).
//! * [`visibility`] — line-of-sight tests of seed 002 eq. 50–52 (ground) and eq. 58–60 (orbiter),
//!   and the [`Beacon`] enum that dispatches between them.
//! * [`ephemeris_table`] — the beacons' states tabulated once per scenario at the measurement
//!   epochs every run shares.
//! * [`config`] — the scenario-file description (`[[beacons]]` tables) with validation.
//!
//! All quantities are SI inside (m, m/s, rad, s); km and degrees appear only in [`config`].
//! States are expressed in the inertial frame of [`crate::frames`], which coincides with the
//! planet-fixed frame at t = 0.

pub mod config;
mod config_validate;
pub mod elements;
pub mod ephemeris_table;
pub mod error;
mod field_checks;
pub mod motion;
pub mod orbiter;
pub mod stumpff;
pub mod surface;
pub mod visibility;

pub use config::{
    BeaconConfig, CircularConfig, ElementsConfig, OrbiterBeaconConfig, SurfaceBeaconConfig,
};
pub use elements::{CircularOrbit, KeplerElements};
pub use ephemeris_table::{BeaconState, EphemerisTable};
pub use error::BeaconError;
pub use motion::BeaconMotion;
pub use orbiter::Orbiter;
pub use stumpff::stumpff;
pub use surface::SurfaceBeacon;
pub use visibility::{
    Beacon, ground_visibility_margin, ground_visible, orbiter_visibility_margin, orbiter_visible,
};
