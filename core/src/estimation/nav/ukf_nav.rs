//! The UKF navigation filter (seed 001 eq. 41–66; no consider states here).

use super::setup::FilterStart;
use super::ukf_common::{epoch_measurements, predict_channels, step_info, substeps};
use super::{NavFilter, StepInfo};
use crate::atmosphere::AtmosphereModel;
use crate::dynamics::{AugmentedParam, EntryModel};
use crate::estimation::EstimationError;
use crate::estimation::ukf::{Ukf, UkfParams, UkfWorkspace};
use crate::math::V3;
use crate::scenario::Scenario;
use crate::sim::MeasurementEpoch;
use nalgebra::{SMatrix, SVector};
use std::sync::Arc;

/// UKF navigation filter with the scenario's α, β, κ (`filter.ukf`). The sigma points are
/// propagated with the truth's RK4 scheme in sub-steps no longer than the filter step.
#[derive(Debug, Clone)]
pub struct UkfNav<const N: usize> {
    scenario: Arc<Scenario>,
    model: EntryModel<AtmosphereModel>,
    ukf: Ukf<N>,
    ws: UkfWorkspace<N>,
    q: SMatrix<f64, N, N>,
    t: f64,
    /// Bank-angle command of the onboard models \[rad\] (starts at the scenario's).
    bank: f64,
}

impl<const N: usize> UkfNav<N> {
    /// A UKF on `scenario` from `start`.
    pub fn new(scenario: &Arc<Scenario>, start: &FilterStart<N>) -> Result<Self, EstimationError> {
        let u = &scenario.config.filter.ukf;
        let params = UkfParams {
            alpha: u.alpha,
            beta: u.beta,
            kappa: u.kappa,
        };
        Ok(UkfNav {
            scenario: Arc::clone(scenario),
            model: scenario.filter_model.clone(),
            ukf: Ukf::new(start.x0, start.p0, params, 0)?,
            ws: UkfWorkspace::default(),
            q: start.q,
            t: 0.0,
            bank: scenario.truth_bank,
        })
    }
}

impl<const N: usize> NavFilter<N> for UkfNav<N> {
    fn predict(&mut self, t_to: f64) -> Result<(), EstimationError> {
        let dt = t_to - self.t;
        if dt <= 0.0 {
            return Ok(());
        }
        let step = self.scenario.config.timing.filter_step_s;
        let (n, h) = substeps(dt, step);
        let bank = self.bank;
        let model = &self.model;
        let q = self.q * (h / step);
        for _ in 0..n {
            self.ukf
                .predict_with(&mut self.ws, |x| model.step(x, bank, h), &q)?;
        }
        self.t = t_to;
        Ok(())
    }

    fn update(
        &mut self,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
    ) -> Result<StepInfo, EstimationError> {
        let Some((slots, z, r)) = epoch_measurements(&self.scenario, epoch) else {
            return Ok(StepInfo::default());
        };
        let (sc, model, t, bank) = (&*self.scenario, &self.model, epoch.t, self.bank);
        let h = |x: &SVector<f64, N>, out: &mut [f64]| {
            predict_channels(sc, model, x, t, bank, beacons, &slots, out);
            Ok(())
        };
        let upd = self.ukf.update_with(&mut self.ws, h, &z, &r)?;
        Ok(step_info(&upd, slots.len()))
    }

    fn estimate(&self) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
        (self.ukf.x, self.ukf.p)
    }

    fn time(&self) -> f64 {
        self.t
    }

    fn set_bank_angle(&mut self, bank_rad: f64) {
        self.bank = bank_rad;
    }

    fn bank_angle(&self) -> f64 {
        self.bank
    }

    fn density_estimate(&self) -> Option<f64> {
        self.model
            .augmented
            .contains(&AugmentedParam::Rho0)
            .then(|| self.model.density(&self.ukf.x))
    }

    fn density_profile(&self, altitude_m: f64) -> Option<f64> {
        self.density_estimate()
            .map(|_| self.model.density_profile(&self.ukf.x, altitude_m))
    }
}
