//! A whole truth run recorded: the batch loop over the engine's truth step, and one Monte Carlo
//! run's truth with its filter start ([`record_run`]), which every filter then flies
//! ([`Navigator::fly`](super::Navigator::fly)).

use super::run_seed::run_seed;
use super::start::initial_estimate;
use super::truth::{SimError, StopReason, TruthSample, TruthStep};
use super::truth_sensors::TruthSensors;
use crate::scenario::{Scenario, TruthDraw};
use crate::sensors::{Channel, MeasurementEpoch};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;
use thiserror::Error;

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

/// The largest value over a run of one load and when it happened.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Peak {
    /// The value (units of the sample's field).
    pub value: f64,
    /// Its time \[s\].
    pub t: f64,
}

/// Peak loads over *every truth integration step* of a run (not only the measurement epochs,
/// which may be seconds apart or absent): aerodynamic deceleration \[m/s²\], dynamic pressure
/// \[Pa\] and heating rate \[W/m²\] of the samples ([`TruthSample`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Peaks {
    /// Aerodynamic (sensed) deceleration.
    pub aero_accel: Peak,
    /// Dynamic pressure.
    pub dynamic_pressure: Peak,
    /// Stagnation-point heating rate.
    pub heating: Peak,
}

impl Peaks {
    fn start(s: &TruthSample) -> Peaks {
        let at = |value: f64| Peak { value, t: s.t };
        Peaks {
            aero_accel: at(s.aero_accel),
            dynamic_pressure: at(s.dynamic_pressure),
            heating: at(s.heating),
        }
    }

    fn see(&mut self, s: &TruthSample) {
        for (p, v) in [
            (&mut self.aero_accel, s.aero_accel),
            (&mut self.dynamic_pressure, s.dynamic_pressure),
            (&mut self.heating, s.heating),
        ] {
            if v > p.value {
                *p = Peak { value: v, t: s.t };
            }
        }
    }
}

/// [`simulate_truth`] and the run's [`Peaks`] over every truth step (costs one truth sample per
/// integration step, which the Monte Carlo does not pay).
pub fn simulate_truth_with_peaks<R: Rng>(
    scenario: &Scenario,
    draw: &TruthDraw,
    rng: &mut R,
) -> Result<(TruthRun, Peaks), SimError> {
    let mut truth = TruthSensors::with_draw(scenario, draw.clone(), rng);
    let first = truth.outputs().sample.clone();
    let mut peaks = Peaks::start(&first);
    let mut samples = vec![first];
    let mut epochs = Vec::new();
    let ended_on_epoch = truth.run_to_end_seeing_steps(
        |e, s| {
            epochs.push(e.clone());
            samples.push(s.clone());
        },
        Some(|s: &TruthSample| peaks.see(s)),
    )?;
    if !ended_on_epoch {
        samples.push(truth.outputs().sample.clone());
    }
    let run = TruthRun {
        samples,
        epochs,
        stop: truth.stop().unwrap_or(StopReason::Duration),
    };
    Ok((run, peaks))
}

impl TruthRun {
    /// Every epoch with the truth sample at its time, in order.
    pub fn epochs_with_truth(&self) -> impl Iterator<Item = (&MeasurementEpoch, &TruthSample)> {
        self.epochs.iter().zip(&self.samples[1..])
    }
}

/// Simulate one truth run of `scenario` for the realisation `draw`, drawing measurement noise
/// from `rng`: [`TruthSensors`] run to the end at the scenario's bank with every beacon available
/// (see the engine's step in [`super`]).
pub fn simulate_truth<R: Rng>(
    scenario: &Scenario,
    draw: &TruthDraw,
    rng: &mut R,
) -> Result<TruthRun, SimError> {
    run_truth(TruthSensors::with_draw(scenario, draw.clone(), rng))
}

/// [`simulate_truth`] along `steps`, the trajectory of `draw` integrated before
/// ([`TruthSensors::with_draw_replaying`]): the same run without integrating it again.
pub fn simulate_truth_replaying<R: Rng>(
    scenario: &Scenario,
    draw: &TruthDraw,
    rng: &mut R,
    steps: Arc<[TruthStep]>,
) -> Result<TruthRun, SimError> {
    run_truth(TruthSensors::with_draw_replaying(
        scenario,
        draw.clone(),
        rng,
        steps,
    ))
}

fn run_truth<R: Rng>(mut truth: TruthSensors<R, &Scenario>) -> Result<TruthRun, SimError> {
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

/// The truth of Monte Carlo run `run` could not be simulated (a scenario problem).
#[derive(Debug, Error, Clone, PartialEq)]
#[error("run {run}: {source}")]
pub struct RunError {
    /// Run index.
    pub run: usize,
    /// Why the truth stopped.
    #[source]
    pub source: SimError,
}

/// One Monte Carlo run's truth, recorded: the realisation, the truth run with its measurement
/// epochs, and the filters' common initial estimate. Filters can fly it any number of times
/// (common random numbers: `entrynav tune` compares tunings on the same runs).
#[derive(Debug, Clone)]
pub struct RecordedRun {
    /// Run index.
    pub run: usize,
    /// The truth realisation.
    pub draw: TruthDraw,
    /// The truth run and its measurement epochs.
    pub truth: TruthRun,
    /// The filters' initial estimate.
    pub x0: Vec<f64>,
}

/// Record run `run` of a study with master seed `seed`.
///
/// Run `run` draws everything from `ChaCha8Rng::seed_from_u64(run_seed(seed, run))`, in this
/// order: the truth dispersions, the measurement noise of the whole run, the initial estimate.
pub fn record_run(scenario: &Scenario, seed: u64, run: usize) -> Result<RecordedRun, RunError> {
    record_run_following(scenario, seed, run, |_| None)
}

/// [`record_run`], following the trajectory `stored` gives for the run's realisation, when it
/// gives one (integrated before for that realisation, `sim/monte_carlo/shared_truth.rs`): the
/// same record.
pub fn record_run_following(
    scenario: &Scenario,
    seed: u64,
    run: usize,
    stored: impl FnOnce(&TruthDraw) -> Option<Arc<[TruthStep]>>,
) -> Result<RecordedRun, RunError> {
    let mut rng = ChaCha8Rng::seed_from_u64(run_seed(seed, run as u64));
    let draw = scenario.draw_truth_run(run, &mut rng);
    let truth = match stored(&draw) {
        Some(steps) => simulate_truth_replaying(scenario, &draw, &mut rng, steps),
        None => simulate_truth(scenario, &draw, &mut rng),
    }
    .map_err(|source| RunError { run, source })?;
    let x0 = initial_estimate(scenario, &draw, &truth.samples[0], &mut rng);
    Ok(RecordedRun {
        run,
        draw,
        truth,
        x0,
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
