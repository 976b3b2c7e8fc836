//! Trained density networks on disk, one or several by altitude band, and the onboard atmosphere
//! they define.
//!
//! A network file is TOML (the core's own format crate; the file ships in `core/scenarios/` next to
//! the scenario and is embedded in the binary, see [`builtin_network_toml`]). It holds one network
//! per altitude band: seed 001 trains one network over the whole entry (§IV.A); its §VI suggests
//! "multiple neural networks ... trained at varying altitudes using a multi-height exponential
//! model", each adapted online while the estimate is inside its band — a file with several
//! bands is that extension ([`DensityNetworkSet`]).

use super::error::NetworkError;
use super::local_fit::LogLinearCorrection;
use super::nn::{Activations, DensityNetwork, Normalisation};
use crate::atmosphere::Atmosphere;
use crate::math::Real;
use serde::{Deserialize, Serialize};

/// Format tag written into every network file.
pub const NETWORK_FORMAT: &str = "entrynav-density-nn-1";

/// File name of the built-in single network for `msl-airdata`.
pub const MSL_AIRDATA_NETWORK: &str = "msl-airdata-density-nn.toml";

/// File name of the built-in three-band networks for `msl-airdata`.
pub const MSL_AIRDATA_BAND_NETWORKS: &str = "msl-airdata-density-nn-bands.toml";

/// Text of a built-in network file (`core/scenarios/<name>`, embedded at compile time), if `name` is one.
pub fn builtin_network_toml(name: &str) -> Option<&'static str> {
    match name {
        MSL_AIRDATA_NETWORK => Some(include_str!(
            "../../../scenarios/msl-airdata-density-nn.toml"
        )),
        MSL_AIRDATA_BAND_NETWORKS => Some(include_str!(
            "../../../scenarios/msl-airdata-density-nn-bands.toml"
        )),
        _ => None,
    }
}

/// Names of the built-in network files.
pub const BUILTIN_NETWORKS: [&str; 2] = [MSL_AIRDATA_NETWORK, MSL_AIRDATA_BAND_NETWORKS];

/// How a network was trained (informative; written by `entrynav train-density`).
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct TrainingRecord {
    /// Scenario the data was generated from.
    pub scenario: String,
    /// Seed of the data generation, split and initialisation.
    pub seed: u64,
    /// Simulated trajectories.
    pub trajectories: usize,
    /// Training samples (after the split).
    pub train_samples: usize,
    /// Validation samples.
    pub validation_samples: usize,
    /// Epochs.
    pub epochs: usize,
    /// Mini-batch size.
    pub batch_size: usize,
    /// Final mean squared error of the normalised output, training set.
    pub train_mse: f64,
    /// Final mean squared error of the normalised output, validation set.
    pub validation_mse: f64,
    /// Validation relative density error |ρ̂ − ρ|/ρ: median, 99th percentile, maximum.
    #[serde(with = "crate::fixed_len::array")]
    #[schemars(with = "[f64; 3]")]
    pub validation_rel_err_p50_p99_max: [f64; 3],
    /// Fraction of validation samples with relative error below 1 % (seed 001 Fig. 5).
    pub validation_frac_below_1pct: f64,
    /// Wall time of the training \[s\] (not reproducible).
    pub wall_time_s: f64,
}

/// One trained network in a file, with the band it covers and the model it was trained on.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NetworkRecord {
    /// Altitudes \[km\] of the band `[bottom, top)` this network serves.
    #[serde(with = "crate::fixed_len::array")]
    #[schemars(with = "[f64; 2]")]
    pub altitude_band_km: [f64; 2],
    /// The exponential it was trained on: `[rho_ref_kgm3, ref_altitude_km, scale_height_km]`.
    #[serde(with = "crate::fixed_len::array")]
    #[schemars(with = "[f64; 3]")]
    pub trained_on_exponential: [f64; 3],
    /// Normalisation and transform constants (seed 001 eq. 29–31).
    pub normalisation: Normalisation,
    /// W⁽ⁱ⁾ (H values).
    pub w_in: Vec<f64>,
    /// b⁽ⁱ⁾ (H values).
    pub b_in: Vec<f64>,
    /// W⁽ᵒ⁾ (H values).
    pub w_out: Vec<f64>,
    /// b⁽ᵒ⁾.
    pub b_out: f64,
    /// How it was trained.
    #[serde(default)]
    pub training: TrainingRecord,
}

/// A network file: a format tag, a description and one network per altitude band.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct NetworkFile {
    /// [`NETWORK_FORMAT`].
    pub format: String,
    /// What the file is.
    pub description: String,
    /// Planet radius the radii are measured against (altitude = r − R) \[m\].
    pub planet_radius_m: f64,
    /// Networks, bands in increasing altitude, contiguous.
    pub networks: Vec<NetworkRecord>,
}

impl NetworkRecord {
    /// The record as a network.
    pub fn to_network(&self) -> Result<DensityNetwork, NetworkError> {
        let h = self.w_in.len();
        if self.b_in.len() != h || self.w_out.len() != h {
            return Err(NetworkError::LayerLengths {
                w_in: h,
                b_in: self.b_in.len(),
                w_out: self.w_out.len(),
            });
        }
        let mut xi = Vec::with_capacity(3 * h + 1);
        xi.extend_from_slice(&self.w_in);
        xi.extend_from_slice(&self.b_in);
        xi.extend_from_slice(&self.w_out);
        xi.push(self.b_out);
        DensityNetwork::new(h, xi, self.normalisation)
    }

    /// A record of `net` for `band_km`, trained on `exponential`.
    pub fn from_network(
        net: &DensityNetwork,
        band_km: [f64; 2],
        exponential: [f64; 3],
        training: TrainingRecord,
    ) -> Self {
        let (w1, b1, w2, b2) = net.layers();
        NetworkRecord {
            altitude_band_km: band_km,
            trained_on_exponential: exponential,
            normalisation: net.norm,
            w_in: w1.to_vec(),
            b_in: b1.to_vec(),
            w_out: w2.to_vec(),
            b_out: b2,
            training,
        }
    }
}

impl NetworkFile {
    /// Parse and check a network file; `source` names it in errors.
    pub fn from_toml_str(text: &str, source: &str) -> Result<NetworkFile, NetworkError> {
        let f: NetworkFile = toml::from_str(text).map_err(|e| NetworkError::Parse {
            source_name: source.to_string(),
            message: e.to_string(),
        })?;
        if f.format != NETWORK_FORMAT {
            return Err(NetworkError::Format {
                source_name: source.to_string(),
                found: f.format.clone(),
                expected: NETWORK_FORMAT,
            });
        }
        f.to_set().map_err(|e| NetworkError::InFile {
            source_name: source.to_string(),
            source: Box::new(e),
        })?;
        Ok(f)
    }

    /// Serialise as TOML.
    pub fn to_toml_string(&self) -> String {
        toml::to_string(self).unwrap_or_else(|e| format!("# serialisation failed: {e}\n"))
    }

    /// The networks as a set ready for use.
    pub fn to_set(&self) -> Result<DensityNetworkSet, NetworkError> {
        let mut nets = Vec::with_capacity(self.networks.len());
        let mut tops = Vec::with_capacity(self.networks.len());
        if self.networks.is_empty() {
            return Err(NetworkError::Empty);
        }
        if !(self.planet_radius_m.is_finite() && self.planet_radius_m > 0.0) {
            return Err(NetworkError::PlanetRadius(self.planet_radius_m));
        }
        for (k, rec) in self.networks.iter().enumerate() {
            let [lo, hi] = rec.altitude_band_km;
            if !(lo.is_finite() && hi.is_finite() && lo < hi) {
                return Err(NetworkError::BandOrder { index: k, lo, hi });
            }
            if k > 0 && (lo - self.networks[k - 1].altitude_band_km[1]).abs() > 1e-9 {
                return Err(NetworkError::BandGap {
                    index: k,
                    lo,
                    previous: k - 1,
                    previous_top: self.networks[k - 1].altitude_band_km[1],
                });
            }
            nets.push(rec.to_network().map_err(|e| NetworkError::InNetwork {
                index: k,
                source: Box::new(e),
            })?);
            tops.push(hi * 1e3);
        }
        Ok(DensityNetworkSet {
            nets,
            tops_m: tops,
            planet_radius_m: self.planet_radius_m,
            correction: LogLinearCorrection::default(),
        })
    }
}

/// One network per altitude band, bands contiguous and increasing; a single network is a set
/// of one. Below the lowest band the lowest network is used, above the highest the highest.
#[derive(Debug, Clone, PartialEq)]
pub struct DensityNetworkSet {
    /// Networks, lowest band first.
    pub nets: Vec<DensityNetwork>,
    /// Top altitude of each band \[m\].
    pub tops_m: Vec<f64>,
    /// Planet radius: altitude h = r − R \[m\].
    pub planet_radius_m: f64,
    /// The local level-and-slope correction every density of the set is multiplied by
    /// (identity without `slope_window`, [`super::local_fit`]).
    pub correction: LogLinearCorrection,
}

impl DensityNetworkSet {
    /// Index of the network serving altitude `h_m`.
    #[inline]
    pub fn band(&self, h_m: f64) -> usize {
        let n = self.tops_m.len();
        self.tops_m[..n - 1]
            .iter()
            .position(|&top| h_m < top)
            .unwrap_or(n - 1)
    }

    /// Density [kg/m³] at altitude `h_m`: the serving network's, times the correction.
    #[inline]
    pub fn density_at_altitude(&self, h_m: f64) -> f64 {
        self.network_density(h_m) * self.correction.factor(h_m)
    }

    /// The serving network's density [kg/m³] at altitude `h_m`, without the correction.
    #[inline]
    pub fn network_density(&self, h_m: f64) -> f64 {
        self.nets[self.band(h_m)].density(h_m + self.planet_radius_m)
    }

    /// Density and dρ/dh at altitude `h_m` (correction included).
    #[inline]
    pub fn density_and_slope(&self, h_m: f64) -> (f64, f64) {
        let (rho, slope) = self.nets[self.band(h_m)].density_and_slope(h_m + self.planet_radius_m);
        let c = &self.correction;
        let f = c.factor(h_m);
        (rho * f, (slope + rho * c.slope_per_m) * f)
    }

    /// Density at altitude `h_m` and `grad_band += weight·∂ρ/∂ξ_band` for the serving network;
    /// returns (ρ, band).
    pub fn density_gradient(
        &self,
        h_m: f64,
        weight: f64,
        grads: &mut [Vec<f64>],
        act: &mut Activations,
    ) -> (f64, usize) {
        let (b, f) = (self.band(h_m), self.correction.factor(h_m));
        let r = h_m + self.planet_radius_m;
        let rho = self.nets[b].density_gradient(r, weight * f, &mut grads[b], act);
        (rho * f, b)
    }
}

/// The onboard atmosphere of the USKF-NN: ρ(h) = NN(R + h, ξ) of the serving band (seed 001
/// eq. 28, 45, 53, 62; the consider factor c multiplies it through the dynamics' density scale),
/// times the set's local correction (identity without `slope_window`).
///
/// Generic evaluation: the value and dρ/dh are computed in `f64` and a dual argument gets the
/// first-order expansion `ρ(h₀) + ρ'(h₀)(h − h₀)`, exact for first derivatives (every AD use in
/// this crate); with `f64` the result is exactly the network's value.
#[derive(Debug, Clone, PartialEq)]
pub struct NnAtmosphere {
    /// The (adapted) networks.
    pub set: DensityNetworkSet,
}

impl Atmosphere for NnAtmosphere {
    fn density<T: Real>(&self, altitude_m: T) -> T {
        let h0 = altitude_m.re();
        // A `Real` the size of one f64 carries no derivative (every dual type holds at least
        // two f64): skip the slope, which the expansion below would multiply by zero.
        if std::mem::size_of::<T>() == std::mem::size_of::<f64>() {
            return T::from(self.set.density_at_altitude(h0));
        }
        let (rho, slope) = self.set.density_and_slope(h0);
        T::from(rho) + (altitude_m - T::from(h0)) * slope
    }
}
