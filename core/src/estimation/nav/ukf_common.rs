//! Pieces the navigation filters share (mostly the UKF family): the prediction sub-steps, the epoch's measurement
//! vector with its noise, the measurement function over sigma points, and the step report.

use super::StepInfo;
use crate::atmosphere::Atmosphere;
use crate::dynamics::EntryModel;
use crate::estimation::ukf::UkfUpdate;
use crate::math::V3;
use crate::scenario::Scenario;
use crate::sensors::channels::kinematics;
use crate::sim::MeasurementEpoch;
use nalgebra::{DMatrix, DVector, SVector};

/// Number and length of the RK4 sub-steps that cover `dt` with steps no longer than `step`.
pub(crate) fn substeps(dt: f64, step: f64) -> (usize, f64) {
    let n = ((dt / step) - 1e-9).ceil().max(1.0) as usize;
    (n, dt / n as f64)
}

/// The channels available at `epoch` (indices into `scenario.channels`), their values z and the
/// diagonal noise covariance R the filters assume; `None` when nothing was measured.
pub(crate) fn epoch_measurements(
    scenario: &Scenario,
    epoch: &MeasurementEpoch,
) -> Option<(Vec<usize>, DVector<f64>, DMatrix<f64>)> {
    let slots: Vec<usize> = epoch
        .values
        .iter()
        .enumerate()
        .filter_map(|(c, v)| v.map(|_| c))
        .collect();
    if slots.is_empty() {
        return None;
    }
    let z = DVector::from_iterator(
        slots.len(),
        slots.iter().map(|&c| epoch.values[c].unwrap_or(0.0)),
    );
    let r = DMatrix::from_diagonal(&DVector::from_iterator(
        slots.len(),
        slots
            .iter()
            .enumerate()
            .map(|(i, &c)| scenario.channels[c].filter_noise.sigma(z[i]).powi(2)),
    ));
    Some((slots, z, r))
}

/// The predicted measurements h(x) of the channels `slots` at epoch time `t` with bank-angle
/// command `bank` \[rad\], written to `out` (one entry per slot): the UKF's measurement function,
/// evaluated at each sigma point.
#[allow(clippy::too_many_arguments)]
pub(crate) fn predict_channels<A: Atmosphere, const L: usize>(
    scenario: &Scenario,
    model: &EntryModel<A>,
    x: &SVector<f64, L>,
    t: f64,
    bank: f64,
    beacons: &[(V3<f64>, V3<f64>)],
    slots: &[usize],
    out: &mut [f64],
) {
    let kin = kinematics(model, x, t);
    for (o, &c) in out.iter_mut().zip(slots) {
        *o = scenario.measurement.evaluate_with(
            model,
            x,
            &kin,
            bank,
            beacons,
            scenario.channels[c].channel,
        );
    }
}

/// What a UKF update of `n_meas` scalar measurements reports.
pub(crate) fn step_info(upd: &UkfUpdate, n_meas: usize) -> StepInfo {
    StepInfo {
        nis: Some(upd.nis),
        n_meas,
        innovations: upd.innovation.iter().copied().collect(),
        weights: None,
    }
}
