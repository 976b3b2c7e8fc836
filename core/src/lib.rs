//! # entrynav — Mars atmospheric-entry navigation core
//!
//! An I/O-free numerical library: planet constants and frames, atmosphere models, entry dynamics
//! (spherical 3-DOF with or without planet rotation, Cartesian inertial), radio beacons,
//! onboard sensors, a truth simulator and the scenario description that ties them together.
//!
//! The physics follows four papers, cited by number throughout the documentation:
//!
//! | seed | paper |
//! |---|---|
//! | 000 | Distributed covariance-intersection fusion with information feedback (DCIFAIF) |
//! | 001 | Giraldo-Grueso, Popov, Zanetti — neural-network density adaptation (USKF-NN) |
//! | 002 | Yu, Cui, Xu, Zhu — Mars-network observability and beacon optimization |
//! | 003 | Deng, Gao, Cui — modified multiple-model adaptive estimation (mixture of experts) |
//!
//! Units are SI (m, s, kg, rad) everywhere inside the library; degrees and kilometres appear only
//! in scenario files and reports.
//!
//! Model code is generic over [`math::Real`], so the same function evaluates in `f64` and in
//! forward-mode dual numbers (`num-dual`) for exact Jacobians.
#![warn(missing_docs)]

pub mod atmosphere;
pub mod beacons;
pub mod dynamics;
pub mod estimation;
pub mod files;
pub mod fixed_len;
pub mod frames;
pub mod guidance;
pub mod lincov;
pub mod math;
pub mod observability;
pub mod pcrlb_recursion;
pub mod planet;
pub mod scenario;
pub mod sensors;
pub mod sim;
pub mod state_dim;

pub use planet::Planet;
