//! Innovation gating and beacon exclusion in front of any navigation filter.
//!
//! [`GatedNav`] wraps a filter: before each measurement update it linearises every available
//! channel at the filter's prior (its own estimate after the prediction, with the onboard
//! measurement model and the noise the filter assumes), applies the χ² gate and the beacon
//! monitor of [`crate::estimation::gating`], and passes the filter the epoch without the rejected
//! channels and without the excluded beacons. Every filter kind gets the same gate, built on
//! what the filter itself believes (x̂⁻, P⁻, R); for the sigma-point filters S is linearised at
//! the prior mean rather than taken from their sigma points, which is the same to first order.

use super::epoch_linearization::linearize_epoch;
use super::gate_report::GateReport;
use super::nav_filter::{FilterCore, NavFilter};
use super::step_info::StepInfo;
use crate::estimation::error::EstimationError;
use crate::estimation::gating::{BeaconMonitor, Gate, GatingConfig};
use crate::estimation::onboard::Onboard;
use crate::math::V3;
use crate::sensors::MeasurementEpoch;
use nalgebra::{DMatrix, DVector};
use std::sync::Arc;

/// A navigation filter behind an innovation gate and a beacon monitor.
pub struct GatedNav<const N: usize> {
    inner: Box<dyn NavFilter<N>>,
    onboard: Arc<Onboard>,
    gate: Gate,
    monitor: BeaconMonitor,
    /// Consecutive epochs with several admitted beacons outside the gate.
    suspect_streak: usize,
}

impl<const N: usize> Clone for GatedNav<N> {
    fn clone(&self) -> Self {
        GatedNav {
            inner: self.inner.clone_box(),
            onboard: Arc::clone(&self.onboard),
            gate: self.gate.clone(),
            monitor: self.monitor.clone(),
            suspect_streak: self.suspect_streak,
        }
    }
}

impl<const N: usize> GatedNav<N> {
    /// `inner` behind the gate `config`, on the same `onboard` models it was built from.
    pub fn new(inner: Box<dyn NavFilter<N>>, onboard: &Arc<Onboard>, config: GatingConfig) -> Self {
        GatedNav {
            inner,
            onboard: Arc::clone(onboard),
            gate: Gate::new(config, onboard.channels.len()),
            monitor: BeaconMonitor::new(&config, onboard.beacons.len()),
            suspect_streak: 0,
        }
    }

    /// Innovations ν = z − h(x̂⁻) and S = H P⁻ Hᵀ + R of the epoch's available channels,
    /// linearised at the filter's prior exactly as its EKF update would be.
    fn innovations(
        &self,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
    ) -> (Vec<usize>, DVector<f64>, DMatrix<f64>) {
        let (x, p) = self.inner.prior();
        let bank = self.inner.bank_angle();
        let (slots, items) = linearize_epoch(
            &self.onboard,
            &self.onboard.model,
            bank,
            &x,
            epoch,
            beacons,
            None,
        );
        let m = slots.len();
        let nu = DVector::from_fn(m, |i, _| items[i].2 - items[i].0);
        let s = DMatrix::from_fn(m, m, |i, j| {
            let hp = items[i].1.dot(&(p * items[j].1));
            if i == j { hp + items[i].3 } else { hp }
        });
        (slots, nu, s)
    }

    /// The gate's decision for an epoch: the epoch the filter may use, and the report.
    fn screen(
        &mut self,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
    ) -> (MeasurementEpoch, GateReport) {
        let (slots, nu, s) = self.innovations(epoch, beacons);
        let (mut accepted, terms) = self.gate.decide(&nu, &s);
        let beacon_of = |c: usize| self.onboard.channels[c].channel.beacon();
        // Per beacon: heard, and whether any of its channels is outside the gate.
        let mut heard: Vec<Option<bool>> = vec![None; self.onboard.beacons.len()];
        for (k, &c) in slots.iter().enumerate() {
            if let Some(b) = beacon_of(c).filter(|b| *b < heard.len()) {
                let outside = !accepted[k];
                heard[b] = Some(heard[b].unwrap_or(false) || outside);
            }
        }
        // One fault at a time: an epoch where several admitted beacons are outside the gate
        // rejects them but counts toward no beacon's exclusion (simultaneous outliers happen;
        // simultaneous beacon faults are assumed not to). When that persists for `exclude_after`
        // epochs the prior, not the beacons, is the likelier culprit (a filter that is off or
        // overconfident); rejecting them all would lock it out for good (with little process
        // noise its P no longer grows), so the gate opens for the radio channels.
        let flagged = heard
            .iter()
            .enumerate()
            .filter(|(b, h)| **h == Some(true) && !self.monitor.is_excluded(*b))
            .count();
        self.suspect_streak = if flagged > 1 {
            self.suspect_streak + 1
        } else {
            0
        };
        let opened = self.suspect_streak >= self.gate.config().exclude_after;
        if flagged > 1 {
            for (b, h) in heard.iter_mut().enumerate() {
                if !self.monitor.is_excluded(b) {
                    *h = None;
                }
            }
        }
        if opened {
            for (k, &c) in slots.iter().enumerate() {
                if beacon_of(c).is_some() {
                    accepted[k] = true;
                }
            }
        }
        let events = self.monitor.record(epoch.t, &heard);
        let mut out = epoch.clone();
        let mut report = GateReport {
            opened,
            terms: slots.iter().copied().zip(terms.iter().copied()).collect(),
            events,
            excluded_beacons: self.monitor.excluded(),
            ..GateReport::default()
        };
        for (k, &c) in slots.iter().enumerate() {
            if beacon_of(c).is_some_and(|b| self.monitor.is_excluded(b)) {
                out.values[c] = None;
                report.withheld.push(c);
            } else if !accepted[k] {
                out.values[c] = None;
                report.rejected.push(c);
            }
        }
        (out, report)
    }
}

impl<const N: usize> NavFilter<N> for GatedNav<N> {
    fn predict(&mut self, t_to: f64) -> Result<(), EstimationError> {
        self.inner.predict(t_to)
    }

    fn update(
        &mut self,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
    ) -> Result<StepInfo, EstimationError> {
        let (screened, report) = self.screen(epoch, beacons);
        self.inner.exclude_beacons(&report.excluded_beacons);
        let mut info = self.inner.update(&screened, beacons)?;
        info.gate = Some(report);
        Ok(info)
    }

    fn core(&self) -> &dyn FilterCore<N> {
        self.inner.core()
    }

    fn core_mut(&mut self) -> &mut dyn FilterCore<N> {
        self.inner.core_mut()
    }

    fn estimate(&self) -> (nalgebra::SVector<f64, N>, nalgebra::SMatrix<f64, N, N>) {
        self.inner.estimate()
    }

    fn prior(&self) -> (nalgebra::SVector<f64, N>, nalgebra::SMatrix<f64, N, N>) {
        self.inner.prior()
    }

    fn exclude_beacons(&mut self, beacons: &[usize]) {
        self.inner.exclude_beacons(beacons);
    }

    fn time(&self) -> f64 {
        self.inner.time()
    }

    fn set_bank_angle(&mut self, bank_rad: f64) {
        self.inner.set_bank_angle(bank_rad);
    }

    fn bank_angle(&self) -> f64 {
        self.inner.bank_angle()
    }

    fn density_estimate(&self) -> Option<f64> {
        self.inner.density_estimate()
    }

    fn density_profile(&self, altitude_m: f64) -> Option<f64> {
        self.inner.density_profile(altitude_m)
    }
}
