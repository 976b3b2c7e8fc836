//! [`load_network_set`]: the density networks an onboard view flies with (USKF-NN), loaded and
//! checked against the onboard planet.

use super::error::NetworkError;
use super::network::{BUILTIN_NETWORKS, DensityNetworkSet, NetworkFile, builtin_network_toml};
use crate::estimation::onboard::Onboard;

/// The USKF-NN network set of `onboard`: its loaded networks if any, else the built-in network
/// file named by `filter.density.network`; checked to be trained for the onboard planet radius.
pub fn load_network_set(onboard: &Onboard) -> Result<DensityNetworkSet, NetworkError> {
    let cfg = onboard.tuning.density_settings();
    let name = cfg.network.trim();
    let set = match &onboard.density_networks {
        Some(set) => set.clone(),
        None => {
            let text = builtin_network_toml(name).ok_or_else(|| NetworkError::UnknownNetwork {
                name: name.to_string(),
                known: BUILTIN_NETWORKS.join(", "),
            })?;
            NetworkFile::from_toml_str(text, name)?.to_set()?
        }
    };
    let r = onboard.model.planet.radius;
    if (set.planet_radius_m - r).abs() > 1e-6 * r {
        return Err(NetworkError::PlanetMismatch {
            name: name.to_string(),
            trained: set.planet_radius_m,
            used: r,
        });
    }
    Ok(set)
}
