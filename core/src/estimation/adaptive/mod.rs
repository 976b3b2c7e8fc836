//! Atmospheric-density adaptation (seed 001): the building blocks of the `ukf-cm`, `ukf-ac` and
//! `uskf-nn` navigation filters (the filters themselves are in [`super::nav`]).
//!
//! * [`covariance_matching`] — Myers–Tapley process-noise covariance matching (eq. 20–21), used
//!   by UKF-CM;
//! * [`nn`] — the 1-100-1 tanh density network (eq. 28–33) with backpropagation;
//! * [`adam`] — the Adam moments and step (eq. 55–60);
//! * [`training`] — offline training on a least-squares exponential fit (Algorithm 1);
//! * [`network`] — network files (one network, or one per altitude band), the built-in trained
//!   networks embedded from `core/scenarios/`, and the network-backed onboard atmosphere;
//! * [`mlo`] — online maximum-likelihood adaptation with Adam and patience (eq. 52–60,
//!   Algorithm 2), optionally over a window of past measurements;
//! * [`config`] — the `[filter.density]` settings and their seed-001 defaults.
//!
//! The Monte Carlo evaluation of the density estimates (eq. 70, Table 6, Fig. 10) and the
//! simulation of Algorithm 1's training trajectories drive the simulation engine, so they live in
//! the simulation layer (`sim::density`).
//!
//! UKF-AC (eq. 24–26) needs no building block beyond the UKF: its correction factor is an
//! augmented random-walk state (see [`super::nav::ukf_ac`]).

pub mod adam;
pub mod config;
pub mod covariance_matching;
pub mod error;
pub mod local_fit;
pub mod mlo;
pub mod network;
pub mod nn;
pub mod onboard_networks;
pub mod training;

pub use adam::Adam;
pub use config::{DensityFilterConfig, DensityTrainingConfig};
pub use covariance_matching::CovarianceMatching;
pub use error::NetworkError;
pub use local_fit::{LocalSlopeFit, LogLinearCorrection};
pub use mlo::{LossContext, LossTerm, MloOutcome, MloSettings, OnlineAdam, maximise_likelihood};
pub use network::{
    BUILTIN_NETWORKS, DensityNetworkSet, NETWORK_FORMAT, NetworkFile, NetworkRecord, NnAtmosphere,
    TrainingRecord, builtin_network_toml,
};
pub use nn::{Activations, DensityNetwork, Normalisation, tanh_fast};
pub use onboard_networks::load_network_set;
pub use training::{
    BandedExponential, TrainedNetwork, TrainingData, fit_onboard_exponential, train_network,
};
