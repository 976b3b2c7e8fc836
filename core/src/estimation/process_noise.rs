//! Process-noise models (`[filter.process_noise]`): the constant diagonal `filter.q_diag`, or that
//! diagonal plus state-noise compensation scaled by the aerodynamic load.
//!
//! **Why.** A density or aerodynamic-coefficient error is a specific-force error proportional to
//! the drag (∝ ρv²): it grows by three orders of magnitude from entry interface to peak
//! deceleration and falls again. A constant Q sized for the peak is far too large early and late;
//! sized for the average, it is optimistic at the peak.
//!
//! **The model** (`model = "aero-scaled"`): an unmodelled specific force along each wind axis `k`
//! (drag axis, side, lift plane) with 1σ
//!
//! ```text
//! σ_k(t) = fraction_k · |a_aero(x̂)| + floor
//! ```
//!
//! correlated over a time τ, taken as the white noise of the same low-frequency power, spectral
//! density `q_k = 2 σ_k² τ` (a first-order Gauss–Markov process's white equivalent; Tapley,
//! Schutz & Born, *Statistical Orbit Determination*, §4.9, state-noise compensation). τ is
//! `correlation_time_s`, or, for an error correlated in altitude over a length `L`
//! (`correlation_length_m`, e.g. the density perturbations' vertical correlation), the time the
//! vehicle takes to cross it, `τ = L / |ḣ|`, capped at [`MAX_CORRELATION_TIME_S`]. It enters the
//! state through `G = ∂ẋ/∂δf` ([`EntryModel::aero_noise_map`]); over a sub-step of length `h`
//! with transition Φ, the trapezoid rule of `Q = ∫ Φ(h,s) G q Gᵀ Φᵀ(h,s) ds`:
//!
//! ```text
//! Q_h = (h/2)·(G q Gᵀ + Φ G q Gᵀ Φᵀ)
//! ```
//!
//! evaluated at the filter's own estimate (never the truth), then added to the constant part
//! `q_diag · h / filter step`.
//!
//! **An estimated density state** (`density-bias`, or `rho0`) may carry the density error
//! itself: with `density_sigma = σ` (a relative 1σ) the state is driven like a first-order
//! Gauss–Markov process with the same τ, white noise of intensity `2σ²/τ` (in the state's units:
//! σ·ρ0_model for ρ0), through the same trapezoid rule (Maybeck, *Stochastic Models, Estimation,
//! and Control* vol. 1, §4.11, the first-order Gauss–Markov shaping filter). With τ = L/|ḣ| the
//! density error decorrelates over a length L of altitude, not of time: its noise is largest
//! where the vehicle descends fastest. The mean reversion −Δ/τ is left out of the dynamics: the
//! density error of a real atmosphere has a part that spans the whole entry (the profile's
//! level) beside the km-scale structure, and the measurements bound the random walk's variance.

use crate::atmosphere::Atmosphere;
use crate::dynamics::{AugmentedParam, EntryModel};
use nalgebra::{SMatrix, SVector};
use serde::{Deserialize, Serialize};

/// Longest correlation time \[s\] of an altitude-correlated error (`correlation_length_m`): near
/// the end of the entry, where the vehicle barely descends, the error is no longer one of the
/// atmosphere it flies through.
pub const MAX_CORRELATION_TIME_S: f64 = 100.0;

/// Largest fraction of |a_aero| a scenario accepts as the 1σ of the unmodelled specific force.
pub const MAX_AERO_FRACTION: f64 = 10.0;

/// Shortest |ḣ| \[m/s\] used for `τ = L/|ḣ|`, so level flight gives the cap, not a division by 0.
const MIN_ALTITUDE_RATE_MPS: f64 = 1e-3;

/// A filter's process-noise model.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(tag = "model", rename_all = "kebab-case", deny_unknown_fields)]
pub enum ProcessNoiseModel {
    /// `filter.q_diag` per filter step, scaled to each sub-step (the default).
    #[default]
    Constant,
    /// `filter.q_diag` plus state-noise compensation scaled by the aerodynamic load.
    AeroScaled(AeroScaledNoise),
}

/// Settings of the aerodynamic-load-scaled state-noise compensation (see the module docs).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct AeroScaledNoise {
    /// 1σ of the unmodelled specific force as a fraction of |a_aero(x̂)|, per wind axis: drag
    /// axis, side, lift plane (e.g. `[0.05, 0.02, 0.02]` for a 5 % density error and an L/D
    /// error of 0.02·|a|).
    pub fraction: [f64; 3],
    /// 1σ floor added on every axis [m/s²] (errors that do not follow the load).
    #[serde(default)]
    pub floor_mps2: f64,
    /// Correlation time τ of the error \[s\]; give this or `correlation_length_m`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub correlation_time_s: Option<f64>,
    /// Correlation length of the error in altitude \[m\]: τ = L/|ḣ| (capped at 100 s).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub correlation_length_m: Option<f64>,
    /// 1σ of the relative density error that an estimated density state (`density-bias`, or
    /// `rho0` scaled by the model's ρ0) follows as a first-order Gauss–Markov process with the
    /// correlation above: the state diffuses at 2σ²/τ per second (0, the default: a random
    /// constant with `q_diag`'s noise alone). See the module documentation.
    #[serde(default, skip_serializing_if = "is_zero")]
    pub density_sigma: f64,
}

fn is_zero(v: &f64) -> bool {
    *v == 0.0
}

/// Largest `density_sigma` a scenario accepts (a 1σ density error of 100 %).
pub const MAX_DENSITY_SIGMA: f64 = 1.0;

impl AeroScaledNoise {
    /// The correlation time at altitude rate `altitude_rate_mps`.
    pub fn correlation_time(&self, altitude_rate_mps: f64) -> f64 {
        match (self.correlation_time_s, self.correlation_length_m) {
            (Some(tau), _) => tau,
            (None, Some(l)) => {
                (l / altitude_rate_mps.abs().max(MIN_ALTITUDE_RATE_MPS)).min(MAX_CORRELATION_TIME_S)
            }
            (None, None) => 0.0,
        }
    }

    /// The load-scaled noise of one sub-step of length `h` with transition `phi`, at the
    /// estimate `x` of a filter flying `model` at bank `bank`.
    pub fn over_substep<A: Atmosphere, const N: usize>(
        &self,
        model: &EntryModel<A>,
        x: &SVector<f64, N>,
        bank: f64,
        h: f64,
        phi: &SMatrix<f64, N, N>,
    ) -> SMatrix<f64, N, N> {
        let map = model.aero_noise_map(x, bank);
        let tau = self.correlation_time(map.altitude_rate_mps);
        let q = SMatrix::<f64, 3, 3>::from_diagonal(&nalgebra::Vector3::from_fn(|k, _| {
            let sigma = self.fraction[k] * map.aero_accel_mps2 + self.floor_mps2;
            2.0 * sigma * sigma * tau
        }));
        let mut m = map.g * q * map.g.transpose();
        if self.density_sigma > 0.0
            && let Some((i, scale)) = density_state(model)
            && i < N
        {
            let sigma = self.density_sigma * scale;
            m[(i, i)] += 2.0 * sigma * sigma / tau.max(f64::MIN_POSITIVE);
        }
        (m + phi * m * phi.transpose()) * (0.5 * h)
    }
}

/// The state index of a filter's density state and the size of a unit relative error in its
/// units: 1 for the density bias Δ (ρ = ρ_model·(1 + Δ)), the model's ρ0 for an estimated ρ0.
fn density_state<A>(model: &EntryModel<A>) -> Option<(usize, f64)> {
    model
        .augmented
        .iter()
        .enumerate()
        .find_map(|(k, a)| match a {
            AugmentedParam::DensityBias => Some((6 + k, 1.0)),
            AugmentedParam::Rho0 => Some((6 + k, model.rho0_model)),
            _ => None,
        })
}

impl ProcessNoiseModel {
    /// The process noise of one sub-step of length `h` (transition `phi`): the constant part
    /// `q_step · h / step` plus the model's state-dependent part at the estimate `x`.
    #[allow(clippy::too_many_arguments)]
    pub fn over_substep<A: Atmosphere, const N: usize>(
        &self,
        q_step: &SMatrix<f64, N, N>,
        step: f64,
        model: &EntryModel<A>,
        x: &SVector<f64, N>,
        bank: f64,
        h: f64,
        phi: &SMatrix<f64, N, N>,
    ) -> SMatrix<f64, N, N> {
        let constant = q_step * (h / step);
        match self {
            ProcessNoiseModel::Constant => constant,
            ProcessNoiseModel::AeroScaled(a) => constant + a.over_substep(model, x, bank, h, phi),
        }
    }

    /// Whether the noise depends on the state (a caller that shares one Q between filters with
    /// the same estimate may then still share it; one with different estimates may not).
    pub fn is_constant(&self) -> bool {
        matches!(self, ProcessNoiseModel::Constant)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn noise(tau: Option<f64>, length: Option<f64>) -> AeroScaledNoise {
        AeroScaledNoise {
            fraction: [0.05, 0.02, 0.02],
            floor_mps2: 0.0,
            correlation_time_s: tau,
            correlation_length_m: length,
            density_sigma: 0.0,
        }
    }

    /// With Φ = I the sub-step noise is h·G q Gᵀ: on a spherical state q_k = 2σ_k²τ enters v as
    /// is, γ over v² and ψ over (v cosγ)², positions and augmented states not at all; the
    /// constant model is q_diag·h/step alone.
    #[test]
    fn substep_noise_closed_form_on_a_spherical_state() {
        let model = crate::dynamics::noise_map::test_model(
            crate::dynamics::DynamicsKind::SphericalRotating,
        );
        let x =
            SVector::<f64, 7>::from_column_slice(&[3_440e3, 0.3, -0.4, 5_500.0, -0.2, 1.0, 0.24]);
        let (v, fpa) = (x[3], x[4]);
        let a = model.aero_noise_map(&x, 0.3).aero_accel_mps2;
        let (h, tau, floor) = (0.5, 4.0, 1e-3);
        let cfg = AeroScaledNoise {
            fraction: [0.05, 0.0, 0.02],
            floor_mps2: floor,
            correlation_time_s: Some(tau),
            correlation_length_m: None,
            density_sigma: 0.0,
        };
        let q_step = SMatrix::<f64, 7, 7>::from_diagonal_element(3.0);
        let eye = SMatrix::<f64, 7, 7>::identity();
        let m = ProcessNoiseModel::AeroScaled(cfg);
        let q = m.over_substep(&q_step, 2.0, &model, &x, 0.3, h, &eye);
        let white = |sigma: f64| 2.0 * sigma * sigma * tau * h;
        let mut want = SMatrix::<f64, 7, 7>::from_diagonal_element(0.75);
        want[(3, 3)] += white(0.05 * a + floor);
        want[(4, 4)] += white(0.02 * a + floor) / (v * v);
        want[(5, 5)] += white(floor) / (v * fpa.cos()).powi(2);
        assert!(
            (q - want).abs().max() < 1e-12 * want.abs().max(),
            "{q}\n{want}"
        );
        let constant =
            ProcessNoiseModel::Constant.over_substep(&q_step, 2.0, &model, &x, 0.3, h, &eye);
        assert_eq!(constant, q_step * 0.25);
    }

    /// An estimated density bias gets 2σ²/τ·h on its own diagonal (Φ = I), with τ = L/|ḣ|; the
    /// rest of the matrix is the load-scaled part as without it.
    #[test]
    fn a_density_state_diffuses_at_the_gauss_markov_rate_in_altitude() {
        let mut model = crate::dynamics::noise_map::test_model(
            crate::dynamics::DynamicsKind::SphericalRotating,
        );
        model.augmented = vec![AugmentedParam::DensityBias];
        let x =
            SVector::<f64, 7>::from_column_slice(&[3_440e3, 0.3, -0.4, 5_500.0, -0.2, 1.0, 0.02]);
        let hdot = x[3] * x[4].sin();
        let (h, length, sigma) = (0.5, 8e3, 0.05);
        let mut cfg = noise(None, Some(length));
        let zero = SMatrix::<f64, 7, 7>::zeros();
        let eye = SMatrix::<f64, 7, 7>::identity();
        let without =
            ProcessNoiseModel::AeroScaled(cfg).over_substep(&zero, 1.0, &model, &x, 0.0, h, &eye);
        cfg.density_sigma = sigma;
        let with =
            ProcessNoiseModel::AeroScaled(cfg).over_substep(&zero, 1.0, &model, &x, 0.0, h, &eye);
        let tau = length / hdot.abs();
        let want = 2.0 * sigma * sigma / tau * h;
        assert!(
            (with[(6, 6)] - want).abs() < 1e-15,
            "{} vs {want}",
            with[(6, 6)]
        );
        let mut rest = with;
        rest[(6, 6)] = without[(6, 6)];
        assert_eq!(rest, without);
        // An estimated ρ0 gets the same relative noise, in kg/m³.
        model.augmented = vec![AugmentedParam::Rho0];
        let rho0 =
            ProcessNoiseModel::AeroScaled(cfg).over_substep(&zero, 1.0, &model, &x, 0.0, h, &eye);
        let want = want * model.rho0_model.powi(2);
        assert!(
            (rho0[(6, 6)] - want).abs() < 1e-12 * want,
            "{}",
            rho0[(6, 6)]
        );
    }

    #[test]
    fn correlation_time_from_length_and_cap() {
        assert_eq!(noise(Some(7.0), Some(8e3)).correlation_time(-1_000.0), 7.0);
        assert_eq!(noise(None, Some(8e3)).correlation_time(-1_000.0), 8.0);
        assert_eq!(
            noise(None, Some(8e3)).correlation_time(0.0),
            MAX_CORRELATION_TIME_S
        );
    }

    #[test]
    fn the_toml_form_parses_and_refuses_unknown_fields() {
        let m: ProcessNoiseModel = toml::from_str(
            "model = \"aero-scaled\"\nfraction = [0.05, 0.02, 0.02]\ncorrelation_length_m = 8000.0",
        )
        .unwrap();
        assert_eq!(m, ProcessNoiseModel::AeroScaled(noise(None, Some(8e3))));
        let c: ProcessNoiseModel = toml::from_str("model = \"constant\"").unwrap();
        assert!(c.is_constant());
        assert!(
            toml::from_str::<ProcessNoiseModel>(
                "model = \"aero-scaled\"\nfraction = [0.05, 0.02, 0.02]\nfractoin = 1.0"
            )
            .is_err()
        );
    }
}
