//! A whole truth run recorded: the batch loop over the engine's truth step.

use super::engine::{SimError, StopReason, TruthSample, TruthSensors};
use crate::scenario::{Scenario, TruthDraw};
use crate::sensors::{Channel, MeasurementEpoch};
use rand::Rng;

/// A complete truth run.
#[derive(Debug, Clone)]
pub struct TruthRun {
    /// Truth samples at t = 0, at every measurement epoch, and at the final time.
    pub samples: Vec<TruthSample>,
    /// Measurement epochs (aligned with `samples[1..]`).
    pub epochs: Vec<MeasurementEpoch>,
    /// Why it ended.
    pub stop: StopReason,
}

impl TruthRun {
    /// Every epoch with the truth sample at its time, in order.
    pub fn epochs_with_truth(&self) -> impl Iterator<Item = (&MeasurementEpoch, &TruthSample)> {
        self.epochs.iter().zip(&self.samples[1..])
    }
}

/// Simulate one truth run of `scenario` for the realisation `draw`, drawing measurement noise
/// from `rng`: [`TruthSensors`] run to the end at the scenario's bank with every beacon available
/// (see the engine's step in [`super::engine`]).
pub fn simulate_truth<R: Rng>(
    scenario: &Scenario,
    draw: &TruthDraw,
    rng: &mut R,
) -> Result<TruthRun, SimError> {
    let mut truth = TruthSensors::with_draw(scenario, draw.clone(), rng);
    let mut samples = vec![truth.outputs().sample.clone()];
    let mut epochs = Vec::new();
    let ended_on_epoch = truth.run_to_end(|e, s| {
        epochs.push(e.clone());
        samples.push(s.clone());
    })?;
    if !ended_on_epoch {
        samples.push(truth.outputs().sample.clone());
    }
    Ok(TruthRun {
        samples,
        epochs,
        stop: truth.stop().unwrap_or(StopReason::Duration),
    })
}

/// Channel names of a scenario, in measurement-slot order.
pub fn channel_names(scenario: &Scenario) -> Vec<String> {
    scenario.channels.iter().map(|c| c.name.clone()).collect()
}

/// Whether a channel is a radio channel (its slots may be empty for outages and visibility).
pub fn is_radio(channel: Channel) -> bool {
    channel.beacon().is_some()
}
