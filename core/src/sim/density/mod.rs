//! Seed 001's density adaptation over a scenario: the offline training of the density networks
//! on trajectories flown by the engine's truth propagator ([`training`], Algorithm 1), and the
//! Monte Carlo evaluation of the filters' density estimates ([`density_eval`], eq. 70, Table 6).

pub mod density_eval;
pub mod training;

pub use density_eval::{
    DensityEvalError, DensityEvalOptions, DensityEvalReport, evaluate_density_filters,
};
pub use training::{generate_data, train_density_networks};
