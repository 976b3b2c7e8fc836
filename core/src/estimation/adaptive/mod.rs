//! Atmospheric-density adaptation (seed 001): the building blocks of the `ukf-cm`, `ukf-ac` and
//! `uskf-nn` navigation filters (the filters themselves are in [`super::nav`]).
//!
//! * [`covariance_matching`] — Myers–Tapley process-noise covariance matching (eq. 20–21), used
//!   by UKF-CM;
//! * [`nn`] — the 1-100-1 tanh density network (eq. 28–33) with backpropagation and Adam;
//! * [`training`] — offline training on a least-squares exponential fit (Algorithm 1);
//! * [`network`] — network files (one network, or one per altitude band), the built-in trained
//!   networks embedded from `scenarios/`, and the network-backed onboard atmosphere;
//! * [`mlo`] — online maximum-likelihood adaptation with Adam and patience (eq. 52–60,
//!   Algorithm 2), optionally over a window of past measurements;
//! * [`evaluate`] — density RMSPE (eq. 70, Table 6) in its two readings and the per-run density
//!   error of Fig. 10.
//!
//! UKF-AC (eq. 24–26) needs no building block beyond the UKF: its correction factor is an
//! augmented random-walk state (see [`super::nav::ukf_ac`]).

pub mod covariance_matching;
pub mod evaluate;
pub mod mlo;
pub mod network;
pub mod nn;
pub mod training;

pub use covariance_matching::CovarianceMatching;
pub use evaluate::{
    DensityEvalOptions, DensityEvalReport, DensityFilter, evaluate_density_filters,
};
pub use mlo::{LossContext, LossTerm, MloOutcome, MloSettings, OnlineAdam, maximise_likelihood};
pub use network::{
    BUILTIN_NETWORKS, DensityNetworkSet, NetworkFile, NetworkRecord, NnAtmosphere,
    builtin_network_toml,
};
pub use nn::{Activations, Adam, DensityNetwork, Normalisation, tanh_fast};
pub use training::{
    BandedExponential, TrainedNetwork, TrainingData, fit_onboard_exponential, generate_data,
    train_density_networks, train_network,
};

use crate::scenario::{DensityFilterConfig, Scenario};

/// The density settings of `scenario` (`filter.density`, or the seed-001 defaults).
pub fn density_config(scenario: &Scenario) -> DensityFilterConfig {
    scenario.config.filter.density.clone().unwrap_or_default()
}

/// Load the network set named by `filter.density.network` (a built-in network file), checking
/// that its planet radius is the scenario's.
pub fn load_network_set(scenario: &Scenario) -> Result<DensityNetworkSet, String> {
    let cfg = density_config(scenario);
    let name = cfg.network.trim();
    let text = builtin_network_toml(name).ok_or_else(|| {
        format!(
            "filter.density.network = '{name}' is not a built-in network file (built-ins: {})",
            BUILTIN_NETWORKS.join(", ")
        )
    })?;
    let file = NetworkFile::from_toml_str(text, name)?;
    let set = file.to_set()?;
    let r = scenario.filter_model.planet.radius;
    if (set.planet_radius_m - r).abs() > 1e-6 * r {
        return Err(format!(
            "network file '{name}' was trained for planet radius {} m but the scenario uses {r} m",
            set.planet_radius_m
        ));
    }
    Ok(set)
}
