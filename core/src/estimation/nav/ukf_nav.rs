//! The UKF navigation filter (seed 001 eq. 41–66; no consider states here).

use super::nav_filter::{FilterCore, NavFilter};
use super::start::FilterStart;
use super::step_info::StepInfo;
use super::ukf_common::UkfCore;
use crate::atmosphere::AtmosphereModel;
use crate::estimation::error::EstimationError;
use crate::estimation::onboard::Onboard;
use crate::estimation::ukf::Ukf;
use crate::math::V3;
use crate::sensors::MeasurementEpoch;
use nalgebra::SMatrix;
use std::sync::Arc;

/// UKF navigation filter with the onboard tuning's α, β, κ (`filter.ukf`). The sigma points are
/// propagated with the truth's RK4 scheme in sub-steps no longer than the filter step.
#[derive(Debug, Clone)]
pub struct UkfNav<const N: usize> {
    core: UkfCore<AtmosphereModel, N>,
    q: SMatrix<f64, N, N>,
}

impl<const N: usize> UkfNav<N> {
    /// A UKF on the `onboard` models from `start`.
    pub fn new(onboard: &Arc<Onboard>, start: &FilterStart<N>) -> Result<Self, EstimationError> {
        let ukf = Ukf::new(
            start.x0,
            start.p0,
            onboard.tuning.ukf,
            onboard.tuning.n_consider,
        )?;
        Ok(UkfNav {
            core: UkfCore::new(onboard, onboard.model.clone(), ukf, None),
            q: start.q,
        })
    }
}

impl<const N: usize> NavFilter<N> for UkfNav<N> {
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

    fn density_profile(&self, altitude_m: f64) -> Option<f64> {
        let (m, x) = (&self.core.model, &self.core.ukf.x);
        m.estimated_density_profile(x, altitude_m)
    }
}
