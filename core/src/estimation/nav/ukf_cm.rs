//! UKF-CM: the UKF with Myers–Tapley process-noise covariance matching (seed 001 §III.A,
//! eq. 20–21, and §V.B "UKF-CM").
//!
//! The filter is the plain UKF of [`super::UkfNav`] on the scenario's onboard density model (for
//! `msl-airdata` the least-squares exponential fit). After every measurement update it records
//! the state innovation x̂⁺ − x̂⁻ and `P⁻ − Q − P⁺`; once a batch of `filter.density.cm_batch`
//! (10) steps is available, every step replaces Q by the Myers–Tapley estimate over the last
//! batch, reset to `diag(|Q̂ᵢᵢ|)` ([`CovarianceMatching`]). No consider analysis (§V.B).

use super::nav_filter::{FilterCore, NavFilter};
use super::start::FilterStart;
use super::step_info::StepInfo;
use super::ukf_common::UkfCore;
use crate::atmosphere::{Atmosphere, AtmosphereModel};
use crate::estimation::adaptive::covariance_matching::CovarianceMatching;
use crate::estimation::error::EstimationError;
use crate::estimation::onboard::Onboard;
use crate::estimation::ukf::Ukf;
use crate::math::V3;
use crate::sensors::MeasurementEpoch;
use nalgebra::{SMatrix, SVector};
use std::sync::Arc;

/// UKF with covariance-matched process noise (`ukf-cm`).
#[derive(Debug, Clone)]
pub struct UkfCmNav<const N: usize> {
    core: UkfCore<AtmosphereModel, N>,
    /// Process noise per filter step currently in use (the tuning's until the first batch).
    q: SMatrix<f64, N, N>,
    cm: CovarianceMatching<N>,
    /// Prior mean, covariance and the process noise added since the last update.
    prior: Option<(SVector<f64, N>, SMatrix<f64, N, N>, SMatrix<f64, N, N>)>,
}

impl<const N: usize> UkfCmNav<N> {
    /// A UKF-CM on the `onboard` models from `start` (batch size from `filter.density.cm_batch`).
    pub fn new(onboard: &Arc<Onboard>, start: &FilterStart<N>) -> Result<Self, EstimationError> {
        let ukf = Ukf::new(
            start.x0,
            start.p0,
            onboard.tuning.ukf,
            onboard.tuning.n_consider,
        )?;
        Ok(UkfCmNav {
            core: UkfCore::new(onboard, onboard.model.clone(), ukf, None),
            q: start.q,
            cm: CovarianceMatching::new(onboard.tuning.density_settings().cm_batch),
            prior: None,
        })
    }

    /// The onboard density profile at altitude `altitude_m` \[kg/m³\] (not adapted by UKF-CM).
    pub fn density_profile(&self, altitude_m: f64) -> f64 {
        self.core.model.atmosphere.density(altitude_m)
    }

    /// The process noise per filter step currently in use.
    pub fn process_noise(&self) -> &SMatrix<f64, N, N> {
        &self.q
    }
}

impl<const N: usize> NavFilter<N> for UkfCmNav<N> {
    fn predict(&mut self, t_to: f64) -> Result<(), EstimationError> {
        let Some(q_added) = self.core.predict(t_to, &self.q)? else {
            return Ok(());
        };
        let (x, p) = (self.core.ukf.x, self.core.ukf.p);
        self.prior = Some(match self.prior.take() {
            // Several predictions without an update: D uses the total noise added.
            Some((_, _, q0)) => (x, p, q0 + q_added),
            None => (x, p, q_added),
        });
        Ok(())
    }

    fn update(
        &mut self,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
    ) -> Result<StepInfo, EstimationError> {
        let info = self.core.update(epoch, beacons)?;
        if info.n_meas > 0
            && let Some((xp, pp, qu)) = self.prior.take()
        {
            self.cm
                .push(&xp, &pp, &qu, &self.core.ukf.x, &self.core.ukf.p);
            if let Some(q) = self.cm.estimate() {
                self.q = q;
            }
        }
        Ok(info)
    }

    fn core(&self) -> &dyn FilterCore<N> {
        &self.core
    }

    fn core_mut(&mut self) -> &mut dyn FilterCore<N> {
        &mut self.core
    }

    fn density_profile(&self, altitude_m: f64) -> Option<f64> {
        Some(Self::density_profile(self, altitude_m))
    }

    /// The onboard model's density at the estimate (UKF-CM does not adapt it).
    fn density_estimate(&self) -> Option<f64> {
        Some(self.core.model.density(&self.core.ukf.x))
    }
}
