//! UKF-AC: the UKF with an augmented density correction factor (seed 001 §III.B, eq. 24–26, and
//! §V.B "UKF-AC").
//!
//! The 8-state msl-airdata filter `[r, lon, lat, v, γ, ψ, B, L/D]` is augmented with
//! 𝒦 = ρ/ρ_nominal (eq. 24–25), so internally it is a 9-state UKF; the density everywhere
//! (dynamics and measurements) is 𝒦·ρ_nominal(r) (eq. 26), with ρ_nominal the scenario's onboard
//! model. 𝒦 is a random walk with P_𝒦,0 = 1e-10 and Q_𝒦 = 1e-7 per filter step
//! (`filter.density.ac_p0`, `ac_q`). No consider analysis: 𝒦 is estimated and updated.
//!
//! Initial 𝒦: seed 001 initialises it "as the ratio between the true density and the nominal
//! density". A filter cannot know a run's true density, so our reading is the ratio of the truth
//! *mean* profile (the one the onboard model was fitted to, before the run's random
//! perturbation) to the onboard model at the filter's initial altitude; `filter.density.ac_initial`
//! overrides it with a number.

use super::setup::FilterStart;
use super::ukf_common::UkfCore;
use super::{NavFilter, StepInfo};
use crate::atmosphere::{Atmosphere, AtmosphereModel};
use crate::estimation::EstimationError;
use crate::estimation::adaptive::density_config;
use crate::estimation::ukf::{Ukf, UkfParams};
use crate::math::V3;
use crate::scenario::Scenario;
use crate::sim::MeasurementEpoch;
use nalgebra::{SMatrix, SVector};
use std::sync::Arc;

/// Augmented dimension: 8 navigation states + 𝒦.
const L: usize = 9;

/// UKF with the augmented density correction factor (`ukf-ac`), for 8-state spherical scenarios.
#[derive(Debug, Clone)]
pub struct UkfAcNav {
    core: UkfCore<AtmosphereModel, L>,
    q: SMatrix<f64, L, L>,
}

/// Embed an 8-state start in the augmented space with extra state `(x, p, q)`.
pub(crate) fn augment_start(
    start: &FilterStart<8>,
    x: f64,
    p: f64,
    q: f64,
) -> (SVector<f64, L>, SMatrix<f64, L, L>, SMatrix<f64, L, L>) {
    let mut x0 = SVector::<f64, L>::zeros();
    x0.fixed_rows_mut::<8>(0).copy_from(&start.x0);
    x0[8] = x;
    let mut p0 = SMatrix::<f64, L, L>::zeros();
    p0.fixed_view_mut::<8, 8>(0, 0).copy_from(&start.p0);
    p0[(8, 8)] = p;
    let mut q0 = SMatrix::<f64, L, L>::zeros();
    q0.fixed_view_mut::<8, 8>(0, 0).copy_from(&start.q);
    q0[(8, 8)] = q;
    (x0, p0, q0)
}

impl UkfAcNav {
    /// A UKF-AC on `scenario` (8 states) from `start`.
    pub fn new(scenario: &Arc<Scenario>, start: &FilterStart<8>) -> Result<Self, EstimationError> {
        let cfg = density_config(scenario);
        let model = scenario.filter_model.clone();
        let k0 = match cfg.ac_initial {
            Some(k) => k,
            None => {
                let h0 = model.altitude(&start.x0);
                let nominal = model.atmosphere.density(h0);
                let mean = scenario.truth_model.atmosphere.density(h0);
                if !(nominal > 0.0 && mean > 0.0) {
                    return Err(EstimationError::InvalidInput(format!(
                        "UKF-AC: cannot form the initial correction factor at altitude {h0} m (truth mean {mean}, onboard {nominal} kg/m³)"
                    )));
                }
                mean / nominal
            }
        };
        let (x0, p0, q) = augment_start(start, k0, cfg.ac_p0, cfg.ac_q);
        let u = &scenario.config.filter.ukf;
        let ukf = Ukf::new(x0, p0, UkfParams::new(u.alpha, u.beta, u.kappa), 0)?;
        // eq. 26: 𝒦 (state 8) scales the onboard density in the dynamics and the measurements.
        Ok(UkfAcNav {
            core: UkfCore::new(scenario, model, ukf, Some(8)),
            q,
        })
    }

    /// The corrected density profile 𝒦̂·ρ_nominal(h) at altitude `altitude_m` [kg/m³] (eq. 26).
    pub fn density_profile(&self, altitude_m: f64) -> f64 {
        self.core.ukf.x[8] * self.core.model.atmosphere.density(altitude_m)
    }

    /// Current correction factor 𝒦 and its variance.
    pub fn correction_factor(&self) -> (f64, f64) {
        (self.core.ukf.x[8], self.core.ukf.p[(8, 8)])
    }
}

impl NavFilter<8> for UkfAcNav {
    fn predict(&mut self, t_to: f64) -> Result<(), EstimationError> {
        let Some((n, h, step)) = self.core.substeps_to(t_to) else {
            return Ok(());
        };
        // 𝒦 has zero derivative (random walk): the RK4 step leaves it unchanged.
        let q = self.q * (h / step);
        self.core.propagate(t_to, n, h, &q, |_, _| {})
    }

    fn update(
        &mut self,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
    ) -> Result<StepInfo, EstimationError> {
        self.core.update(epoch, beacons)
    }

    fn estimate(&self) -> (SVector<f64, 8>, SMatrix<f64, 8, 8>) {
        self.core.estimate::<8>()
    }

    fn time(&self) -> f64 {
        self.core.t
    }

    fn set_bank_angle(&mut self, bank_rad: f64) {
        self.core.bank = bank_rad;
    }

    fn bank_angle(&self) -> f64 {
        self.core.bank
    }

    fn density_profile(&self, altitude_m: f64) -> Option<f64> {
        Some(Self::density_profile(self, altitude_m))
    }

    /// 𝒦̂·ρ_nominal(r̂) (eq. 26).
    fn density_estimate(&self) -> Option<f64> {
        Some(Self::density_profile(
            self,
            self.core.model.altitude(&self.core.ukf.x),
        ))
    }
}
