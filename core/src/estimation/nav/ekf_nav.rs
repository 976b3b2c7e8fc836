//! The EKF navigation filter: centralised over every channel, or local over a channel subset.

use super::epoch_linearization::{epoch_channels, linearize_epoch};
use super::nav_filter::{FilterCore, NavFilter};
use super::start::FilterStart;
use super::step_info::StepInfo;
use super::ukf_common::substeps;
use crate::atmosphere::AtmosphereModel;
use crate::dynamics::EntryModel;
use crate::estimation::ekf::Ekf;
use crate::estimation::error::EstimationError;
use crate::estimation::linearization::LinearizedMeasurement;
use crate::estimation::onboard::Onboard;
use crate::estimation::process_noise::ProcessNoiseModel;
use crate::math::V3;
use crate::math::all_finite;
use crate::sensors::MeasurementEpoch;
use crate::sensors::channels::kinematics;
use nalgebra::{SMatrix, SVector};
use std::sync::Arc;

/// The iterated EKF stops once a linearisation predicts the measurements at the next iterate to
/// this fraction of their σ ([`Ekf::update_iterated`]).
pub const RELINEARIZATION_TOLERANCE: f64 = 0.01;

/// EKF navigation filter (seed 000 eq. 17–18).
///
/// * Time update: the mean is propagated with the truth's RK4 scheme in sub-steps no longer than
///   `timing.filter_step_s`; Φ is the linearised transition matrix e^{hA} to fourth order
///   ([`EntryModel::step_with_linear_stm`], A = ∂f/∂x by AD),
///   P⁻ = Φ P Φᵀ + Q·(h / filter step).
/// * Measurement update: all available channels of the epoch, linearised at the prior with one AD
///   pass, processed sequentially in Joseph form — identical to the batch update with diagonal R.
///   Relative-noise channels use σ = fraction·|z|.
#[derive(Debug, Clone)]
pub struct EkfNav<const N: usize> {
    onboard: Arc<Onboard>,
    model: EntryModel<AtmosphereModel>,
    ekf: Ekf<N>,
    q: SMatrix<f64, N, N>,
    t: f64,
    channels: Option<Vec<usize>>,
    /// Bank-angle command of the onboard models \[rad\] (starts at the onboard initial bank).
    bank: f64,
}

impl<const N: usize> EkfNav<N> {
    /// A filter on the `onboard` models from `start`; `channels` restricts it to those channel
    /// slots (a local filter), `density_factor` scales its density model (a bank member with bias
    /// Δ: 1 + Δ).
    pub fn new(
        onboard: &Arc<Onboard>,
        start: &FilterStart<N>,
        channels: Option<Vec<usize>>,
        density_factor: f64,
    ) -> Result<Self, EstimationError> {
        let mut model = onboard.model.clone();
        model.density_factor = density_factor;
        Ok(EkfNav {
            onboard: Arc::clone(onboard),
            model,
            ekf: Ekf::new(start.x0, start.p0)?.with_consider(onboard.tuning.n_consider)?,
            q: start.q,
            t: 0.0,
            channels,
            bank: onboard.initial_bank,
        })
    }

    /// Replace the estimate (information feedback, seed 000 eq. 22).
    pub fn set_estimate(&mut self, x: SVector<f64, N>, p: SMatrix<f64, N, N>) {
        self.ekf.x = x;
        self.ekf.p = p;
    }

    /// The sub-steps `(n, h, Q_h)` that take the estimate to `t_to` (`n = 0` when `t_to` is not
    /// later than the filter time); an error past the sub-step limit. `Q_h` is the constant part
    /// of the process noise; [`EkfNav::substep_noise`] adds the state-dependent part.
    pub fn substeps_to(
        &self,
        t_to: f64,
    ) -> Result<(usize, f64, SMatrix<f64, N, N>), EstimationError> {
        let dt = t_to - self.t;
        if dt <= 0.0 {
            return Ok((0, 0.0, SMatrix::zeros()));
        }
        let step = self.onboard.filter_step_s;
        let (n, h) = substeps(dt, step)?;
        Ok((n, h, self.q * (h / step)))
    }

    /// One RK4 sub-step of length `h` of the current estimate: `(x_next, Φ)`.
    pub fn substep(&self, h: f64) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
        self.model.step_with_linear_stm(&self.ekf.x, self.bank, h)
    }

    /// The process noise of one sub-step of length `h` with transition `phi` from the current
    /// estimate: the constant part `q_h` plus the process-noise model's state-dependent part
    /// ([`ProcessNoiseModel`]).
    pub fn substep_noise(
        &self,
        h: f64,
        phi: &SMatrix<f64, N, N>,
        q_h: &SMatrix<f64, N, N>,
    ) -> SMatrix<f64, N, N> {
        match self.onboard.tuning.process_noise {
            ProcessNoiseModel::Constant => *q_h,
            ProcessNoiseModel::AeroScaled(a) => {
                q_h + a.over_substep(&self.model, &self.ekf.x, self.bank, h, phi)
            }
        }
    }

    /// Apply one sub-step (from [`EkfNav::substep`] of a filter with the same estimate).
    pub fn apply_substep(
        &mut self,
        x_next: SVector<f64, N>,
        phi: &SMatrix<f64, N, N>,
        q: &SMatrix<f64, N, N>,
    ) -> Result<(), EstimationError> {
        self.ekf.predict(x_next, phi, q)
    }

    /// Set the filter time after a prediction to `t_to`.
    pub fn finish_prediction(&mut self, t_to: f64) {
        self.t = self.t.max(t_to);
    }

    /// The slots and items of `items` on this filter's channels.
    fn own_items(
        &self,
        items: &[(usize, LinearizedMeasurement<N>)],
    ) -> (Vec<usize>, Vec<LinearizedMeasurement<N>>) {
        let mut slots = Vec::with_capacity(items.len());
        let mut mine = Vec::with_capacity(items.len());
        for (c, it) in items {
            if self.channels.as_ref().is_none_or(|m| m.contains(c)) {
                slots.push(*c);
                mine.push(*it);
            }
        }
        (slots, mine)
    }

    /// Measurement update with precomputed linearised items (channel slot, item); only the slots
    /// this filter uses are applied.
    pub fn update_with_items(
        &mut self,
        items: &[(usize, LinearizedMeasurement<N>)],
    ) -> Result<StepInfo, EstimationError> {
        let (slots, mine) = self.own_items(items);
        if mine.is_empty() {
            return Ok(StepInfo::default());
        }
        let prior = self.ekf.x;
        let (innovations, terms, nis) = self.ekf.update_linearized(&prior, &mine)?;
        if !all_finite(self.ekf.x.as_slice()) {
            return Err(EstimationError::NonFinite {
                what: "updated state".into(),
            });
        }
        Ok(StepInfo {
            nis: Some(nis),
            n_meas: mine.len(),
            innovations,
            weights: None,
            nis_terms: slots.into_iter().zip(terms).collect(),
            gate: None,
        })
    }

    /// Measurement update of this filter's channels from `items` linearised at the prior, iterated
    /// when `filter.update_iterations` > 1 ([`Ekf::update_iterated`], relinearising every channel
    /// at each iterate). One iteration is the standard EKF. With seed 000's 12 km initial position
    /// errors one linearisation of the ranges is off by ~10 m (several σ), so the standard EKF's
    /// first updates are overconfident; the iterated update removes that.
    pub fn update_iterated(
        &mut self,
        items: &[(usize, LinearizedMeasurement<N>)],
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
    ) -> Result<StepInfo, EstimationError> {
        let iterations = self.onboard.tuning.update_iterations;
        if iterations <= 1 {
            return self.update_with_items(items);
        }
        let (slots, first) = self.own_items(items);
        if first.is_empty() {
            return Ok(StepInfo::default());
        }
        let mut ekf = self.ekf.clone();
        let (terms, nis) = ekf.update_iterated(
            &first,
            iterations,
            RELINEARIZATION_TOLERANCE,
            |x| self.values_at(x, epoch, beacons, &slots),
            |x| self.linearize(x, epoch, beacons, Some(&slots)).1,
        )?;
        self.ekf = ekf;
        Ok(StepInfo {
            nis: Some(nis),
            n_meas: first.len(),
            innovations: first.iter().map(|(h0, _, z, _)| z - h0).collect(),
            weights: None,
            nis_terms: slots.into_iter().zip(terms).collect(),
            gate: None,
        })
    }

    /// Linearised items for every available channel of the epoch (ignoring this filter's mask).
    pub fn all_measurement_items(
        &self,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
    ) -> Vec<(usize, LinearizedMeasurement<N>)> {
        let (slots, items) = self.items_for(epoch, beacons, None);
        slots.into_iter().zip(items).collect()
    }

    /// Measurement-update iterations (`filter.update_iterations`; 1 is the standard EKF).
    pub fn update_iterations(&self) -> usize {
        self.onboard.tuning.update_iterations
    }

    /// The channel slots this filter uses (all when it is not a local filter).
    pub fn channel_mask(&self) -> &[usize] {
        match &self.channels {
            Some(m) => m,
            None => &[],
        }
    }

    /// The filter's dynamics model.
    pub fn model(&self) -> &EntryModel<AtmosphereModel> {
        &self.model
    }

    /// Linearised measurement items `(h(x⁻), H, z, r)` for the epoch's available channels,
    /// with the channel slot of each.
    pub fn measurement_items(
        &self,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
    ) -> (Vec<usize>, Vec<LinearizedMeasurement<N>>) {
        self.items_for(epoch, beacons, self.channels.as_deref())
    }

    fn items_for(
        &self,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
        mask: Option<&[usize]>,
    ) -> (Vec<usize>, Vec<LinearizedMeasurement<N>>) {
        self.linearize(&self.ekf.x, epoch, beacons, mask)
    }

    /// Items for the channel `slots` (all available in the epoch) linearised at `x`.
    pub fn items_at(
        &self,
        x: &SVector<f64, N>,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
        slots: &[usize],
    ) -> Vec<LinearizedMeasurement<N>> {
        self.linearize(x, epoch, beacons, Some(slots)).1
    }

    /// The measurement values `h(x)` of the epoch's channels in `slots` (the `.0` of
    /// [`EkfNav::items_at`], without the AD Jacobians).
    pub fn values_at(
        &self,
        x: &SVector<f64, N>,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
        slots: &[usize],
    ) -> Vec<f64> {
        let kin = kinematics(&self.model, x, epoch.t);
        let mut triad = None;
        epoch_channels(&self.onboard, epoch, Some(slots))
            .map(|(_, spec, _)| {
                self.onboard.measurement.evaluate_sharing_triad(
                    &self.model,
                    x,
                    &kin,
                    self.bank,
                    beacons,
                    spec.channel,
                    &mut triad,
                )
            })
            .collect()
    }

    fn linearize(
        &self,
        x: &SVector<f64, N>,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
        mask: Option<&[usize]>,
    ) -> (Vec<usize>, Vec<LinearizedMeasurement<N>>) {
        linearize_epoch(
            &self.onboard,
            &self.model,
            self.bank,
            x,
            epoch,
            beacons,
            mask,
        )
    }
}

impl<const N: usize> NavFilter<N> for EkfNav<N> {
    fn predict(&mut self, t_to: f64) -> Result<(), EstimationError> {
        let (n, h, q) = self.substeps_to(t_to)?;
        for _ in 0..n {
            let (x_next, phi) = self.substep(h);
            let q_k = self.substep_noise(h, &phi, &q);
            self.apply_substep(x_next, &phi, &q_k)?;
        }
        self.finish_prediction(t_to);
        Ok(())
    }

    fn update(
        &mut self,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
    ) -> Result<StepInfo, EstimationError> {
        // Only this filter's channels (a local filter's mask): the others would be linearised
        // only to be dropped.
        let (slots, items) = self.measurement_items(epoch, beacons);
        let items: Vec<_> = slots.into_iter().zip(items).collect();
        self.update_iterated(&items, epoch, beacons)
    }

    fn core(&self) -> &dyn FilterCore<N> {
        self
    }

    fn core_mut(&mut self) -> &mut dyn FilterCore<N> {
        self
    }

    fn density_profile(&self, altitude_m: f64) -> Option<f64> {
        self.model
            .estimated_density_profile(&self.ekf.x, altitude_m)
    }
}

/// An EKF is its own core: one filter, one estimate.
impl<const N: usize> FilterCore<N> for EkfNav<N> {
    fn state(&self) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
        (self.ekf.x, self.ekf.p)
    }

    fn t(&self) -> f64 {
        self.t
    }

    fn bank(&self) -> f64 {
        self.bank
    }

    fn set_bank(&mut self, bank_rad: f64) {
        self.bank = bank_rad;
    }

    fn altitude(&self) -> f64 {
        self.model.altitude(&self.ekf.x)
    }
}
