//! An epoch's available channels linearised at an estimate ([`linearize_epoch`]): the values,
//! Jacobian rows (forward AD) and the noise the filter assumes, which the EKFs' updates and the
//! innovation gate share.

use crate::atmosphere::AtmosphereModel;
use crate::dynamics::EntryModel;
use crate::estimation::linearization::LinearizedMeasurement;
use crate::estimation::onboard::Onboard;
use crate::estimation::onboard::OnboardChannel;
use crate::math::V3;
use crate::math::dual_gradient;
use crate::math::seed_duals;
use crate::sensors::MeasurementEpoch;
use crate::sensors::channels::kinematics_ad;
use nalgebra::SVector;

/// The epoch's available channels (those in `mask`, when given): slot, onboard channel and
/// measured value, in slot order.
pub(super) fn epoch_channels<'a>(
    onboard: &'a Onboard,
    epoch: &'a MeasurementEpoch,
    mask: Option<&'a [usize]>,
) -> impl Iterator<Item = (usize, &'a OnboardChannel, f64)> + 'a {
    epoch
        .values
        .iter()
        .enumerate()
        .filter_map(move |(c, value)| {
            let z = (*value)?;
            if mask.is_some_and(|m| !m.contains(&c)) {
                return None;
            }
            Some((c, onboard.channels.get(c)?, z))
        })
}

/// Linearised items `(h(x), ∂h/∂x by AD, z, r)` of the epoch's available channels (those in
/// `mask`, when given) at `x`, with the `onboard` measurement model on the dynamics `model`
/// flying `bank`, and the noise the filter assumes; with the channel slot of each. The EKFs'
/// update and the innovation gate ([`super::GatedNav`]) share it.
pub(super) fn linearize_epoch<const N: usize>(
    onboard: &Onboard,
    model: &EntryModel<AtmosphereModel>,
    bank: f64,
    x: &SVector<f64, N>,
    epoch: &MeasurementEpoch,
    beacons: &[(V3<f64>, V3<f64>)],
    mask: Option<&[usize]>,
) -> (Vec<usize>, Vec<LinearizedMeasurement<N>>) {
    let xd = seed_duals(x);
    let kin = kinematics_ad(model, x, &xd, epoch.t);
    let mut triad = None;
    let n = mask.map_or(epoch.values.len(), <[usize]>::len);
    let mut slots = Vec::with_capacity(n);
    let mut items = Vec::with_capacity(n);
    for (c, spec, z) in epoch_channels(onboard, epoch, mask) {
        let d = onboard.measurement.evaluate_sharing_triad(
            model,
            &xd,
            &kin,
            bank,
            beacons,
            spec.channel,
            &mut triad,
        );
        let sigma = channel_sigma(spec, z);
        slots.push(c);
        items.push((d.re, dual_gradient(&d), z, sigma * sigma));
    }
    (slots, items)
}

/// Noise 1σ the filters assume for a channel with measured value `z`.
pub(super) fn channel_sigma(spec: &OnboardChannel, z: f64) -> f64 {
    spec.noise.sigma(z)
}
