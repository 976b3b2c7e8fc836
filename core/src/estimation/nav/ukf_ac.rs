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
//! density". A filter cannot know a run's true density, so our reading is the ratio of the
//! pre-flight climatology ([`Onboard::climatology`]: the mean profile the onboard model was
//! fitted to, before any run's random perturbation) to the onboard model at the filter's initial
//! altitude; `filter.density.ac_initial` overrides it with a number.
//!
//! The filter is generic over the navigation dimension `N` (8 for seed 001's layout) with
//! `L = N + 1` internal states.

use super::nav_filter::{FilterCore, NavFilter};
use super::start::FilterStart;
use super::step_info::StepInfo;
use super::ukf_common::UkfCore;
use crate::atmosphere::{Atmosphere, AtmosphereModel};
use crate::estimation::error::EstimationError;
use crate::estimation::onboard::Onboard;
use crate::estimation::ukf::Ukf;
use crate::math::V3;
use crate::sensors::MeasurementEpoch;
use nalgebra::{SMatrix, SVector};
use std::sync::Arc;

/// UKF with the augmented density correction factor (`ukf-ac`): `N` navigation states plus 𝒦,
/// `L = N + 1` states inside.
#[derive(Debug, Clone)]
pub struct UkfAcNav<const N: usize, const L: usize> {
    core: UkfCore<AtmosphereModel, L>,
    q: SMatrix<f64, L, L>,
}

/// Embed an `N`-state start in the `L = N + 1`-state augmented space with extra state
/// `(x, p, q)`.
pub(crate) fn augment_start<const N: usize, const L: usize>(
    start: &FilterStart<N>,
    x: f64,
    p: f64,
    q: f64,
) -> Result<FilterStart<L>, EstimationError> {
    if L != N + 1 {
        return Err(EstimationError::InvalidInput(format!(
            "an augmented filter over {N} navigation states needs {} internal states, not {L}",
            N + 1
        )));
    }
    let mut x0 = SVector::<f64, L>::zeros();
    x0.fixed_rows_mut::<N>(0).copy_from(&start.x0);
    x0[N] = x;
    let mut p0 = SMatrix::<f64, L, L>::zeros();
    p0.fixed_view_mut::<N, N>(0, 0).copy_from(&start.p0);
    p0[(N, N)] = p;
    let mut q0 = SMatrix::<f64, L, L>::zeros();
    q0.fixed_view_mut::<N, N>(0, 0).copy_from(&start.q);
    q0[(N, N)] = q;
    Ok(FilterStart { x0, p0, q: q0 })
}

impl<const N: usize, const L: usize> UkfAcNav<N, L> {
    /// A UKF-AC on the `onboard` models from `start`.
    pub fn new(onboard: &Arc<Onboard>, start: &FilterStart<N>) -> Result<Self, EstimationError> {
        let cfg = onboard.tuning.density_settings();
        let model = onboard.model.clone();
        let k0 = match cfg.ac_initial {
            Some(k) => k,
            None => {
                let h0 = model.altitude(&start.x0);
                let nominal = model.atmosphere.density(h0);
                let mean = onboard.climatology.density(h0);
                if !(nominal > 0.0 && mean > 0.0) {
                    return Err(EstimationError::InvalidInput(format!(
                        "UKF-AC: cannot form the initial correction factor at altitude {h0} m (climatology {mean}, onboard {nominal} kg/m³)"
                    )));
                }
                mean / nominal
            }
        };
        let aug = augment_start::<N, L>(start, k0, cfg.ac_p0, cfg.ac_q)?;
        let ukf = Ukf::new(aug.x0, aug.p0, onboard.tuning.ukf, 0)?;
        // eq. 26: 𝒦 (state N) scales the onboard density in the dynamics and the measurements.
        Ok(UkfAcNav {
            core: UkfCore::new(onboard, model, ukf, Some(N)),
            q: aug.q,
        })
    }

    /// The corrected density profile 𝒦̂·ρ_nominal(h) at altitude `altitude_m` [kg/m³] (eq. 26).
    pub fn density_profile(&self, altitude_m: f64) -> f64 {
        self.core.ukf.x[N] * self.core.model.atmosphere.density(altitude_m)
    }

    /// Current correction factor 𝒦 and its variance.
    pub fn correction_factor(&self) -> (f64, f64) {
        (self.core.ukf.x[N], self.core.ukf.p[(N, N)])
    }
}

impl<const N: usize, const L: usize> NavFilter<N> for UkfAcNav<N, L> {
    /// 𝒦 has zero derivative (random walk): the RK4 step leaves it unchanged.
    fn predict(&mut self, t_to: f64) -> Result<(), EstimationError> {
        self.core.predict(t_to, &self.q).map(|_| ())
    }

    fn update(
        &mut self,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
    ) -> Result<StepInfo, EstimationError> {
        self.core.update(epoch, beacons)
    }

    fn core(&self) -> &dyn FilterCore<N> {
        &self.core
    }

    fn core_mut(&mut self) -> &mut dyn FilterCore<N> {
        &mut self.core
    }

    /// 𝒦̂·ρ_nominal(h) (eq. 26); at the estimate's altitude it is the density estimate.
    fn density_profile(&self, altitude_m: f64) -> Option<f64> {
        Some(Self::density_profile(self, altitude_m))
    }
}
