//! [`TruthSensors`]: the truth trajectory and the measurement records, communication step by
//! communication step.

use super::error::EngineError;
use super::step_check::check_step;
use super::truth::{
    EpochSchedule, SimError, StopReason, TruthAtEpoch, TruthPropagator, TruthSample, TruthStep,
    measure_epoch, truth_sample,
};
use crate::scenario::{Scenario, TruthDraw};
use crate::sensors::channels::kinematics;
use crate::sensors::{Channel, MeasurementEpoch, range, range_rate};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use std::ops::Deref;
use std::sync::Arc;

/// The truth realisation of `seed` (dispersed, or the nominal truth) and the generator positioned
/// for the measurement noise.
pub(crate) fn truth_draw(
    scenario: &Scenario,
    seed: u64,
    dispersed: bool,
) -> (TruthDraw, ChaCha8Rng) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let draw = if dispersed {
        scenario.draw_truth(&mut rng)
    } else {
        scenario.nominal_truth()
    };
    (draw, rng)
}

/// The truth at the current communication point, with derived outputs.
#[derive(Debug, Clone, PartialEq)]
pub struct TruthOutputs {
    /// The truth sample (state, spherical state, altitude, density, dynamic pressure, heating,
    /// aerodynamic acceleration, geometric visibility per beacon).
    pub sample: TruthSample,
    /// Noiseless accelerometer reading (specific force in the IMU frame) [m/s²].
    pub sensed_accel: [f64; 3],
    /// Geometric range to each beacon \[m\].
    pub ranges: Vec<f64>,
    /// Range-rate to each beacon [m/s].
    pub range_rates: Vec<f64>,
}

/// What one step did.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct StepReport {
    /// Truth integration steps taken.
    pub truth_steps: usize,
    /// Measurement epochs generated (truth) or processed (filter).
    pub epochs: usize,
}

/// Truth trajectory and sensors, advanced step by step.
///
/// A channel of period P is sampled at t = P, 2P, … (every sensor period is validated to be a
/// multiple of the truth step); the noise comes from the generator `R` (see the engine step in [`super`]).
/// `S` is how the scenario is held: shared (`Arc`, the FMUs) or borrowed (a batch run).
#[derive(Debug, Clone)]
pub struct TruthSensors<R = ChaCha8Rng, S = Arc<Scenario>> {
    scenario: S,
    draw: TruthDraw,
    rng: R,
    propagator: TruthPropagator,
    periods: Vec<usize>,
    time: f64,
    outputs: TruthOutputs,
    last_epoch: Option<MeasurementEpoch>,
    /// Per channel, the value a stuck fault holds (`[[faults]]` `range-stuck`).
    held: Vec<Option<f64>>,
    /// The trajectory of this realisation at the scenario's bank, integrated before
    /// ([`TruthSensors::with_draw_replaying`]); followed while the bank is the scenario's.
    replay: Option<Arc<[TruthStep]>>,
}

impl TruthSensors<ChaCha8Rng, Arc<Scenario>> {
    /// Start at t = 0 from the truth realisation of `seed` (dispersed or nominal), with the
    /// scenario's bank angle for the initial outputs.
    pub fn new(scenario: Arc<Scenario>, seed: u64, dispersed: bool) -> Self {
        let (draw, rng) = truth_draw(&scenario, seed, dispersed);
        Self::with_draw(scenario, draw, rng)
    }
}

impl<R: Rng, S: Deref<Target = Scenario>> TruthSensors<R, S> {
    /// Start at t = 0 from the realisation `draw`, drawing the measurement noise from `rng`.
    pub fn with_draw(scenario: S, draw: TruthDraw, rng: R) -> Self {
        let propagator = TruthPropagator::for_scenario(&scenario, draw.initial);
        let dt = propagator.dt();
        let periods = scenario
            .channels
            .iter()
            .map(|c| (c.period_s / dt).round().max(1.0) as usize)
            .collect();
        let sample = truth_sample(&scenario, &draw, 0.0, &draw.initial, scenario.truth_bank);
        let mut out = TruthSensors {
            outputs: TruthOutputs {
                sample,
                sensed_accel: [0.0; 3],
                ranges: vec![],
                range_rates: vec![],
            },
            scenario,
            draw,
            rng,
            propagator,
            periods,
            time: 0.0,
            last_epoch: None,
            held: Vec::new(),
            replay: None,
        };
        out.held = vec![None; out.scenario.channels.len()];
        let bank = out.scenario.truth_bank;
        out.refresh_outputs(None, bank);
        out
    }

    /// [`TruthSensors::with_draw`] following `steps`, the trajectory of `draw` at the scenario's
    /// bank that [`TruthPropagator::for_scenario`] integrated before (the Monte Carlo runs of a
    /// realisation shared by every run, `sim/shared_truth.rs`), instead of integrating it again:
    /// the same steps, so the same run. A step at another bank integrates from there on.
    pub fn with_draw_replaying(
        scenario: S,
        draw: TruthDraw,
        rng: R,
        steps: Arc<[TruthStep]>,
    ) -> Self {
        let mut out = Self::with_draw(scenario, draw, rng);
        out.replay = Some(steps);
        out
    }

    /// The next truth step at `bank`: followed from the replay while the bank is the
    /// scenario's, integrated otherwise.
    fn next_step(&mut self, bank: f64) -> Result<Option<TruthStep>, SimError> {
        if let Some(steps) = &self.replay {
            if bank.to_bits() == self.scenario.truth_bank.to_bits() {
                return Ok(self.propagator.follow(steps));
            }
            self.replay = None;
        }
        self.propagator.step(&self.draw.model, bank)
    }

    /// The scenario.
    pub fn scenario(&self) -> &S {
        &self.scenario
    }

    /// The truth realisation.
    pub fn draw(&self) -> &TruthDraw {
        &self.draw
    }

    /// The noise generator, positioned after the last measurement drawn.
    pub fn into_rng(self) -> R {
        self.rng
    }

    /// Current communication point \[s\].
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Why the truth stopped (ground, stop speed, duration), if it has.
    pub fn stop(&self) -> Option<StopReason> {
        self.propagator.stop()
    }

    /// Outputs at the current communication point (the truth of the last integration step at or
    /// before it; the truth holds its final state once it has stopped).
    pub fn outputs(&self) -> &TruthOutputs {
        &self.outputs
    }

    /// The last measurement epoch generated during the last step (None if there was none).
    pub fn last_epoch(&self) -> Option<&MeasurementEpoch> {
        self.last_epoch.as_ref()
    }

    fn refresh_outputs(&mut self, sample: Option<TruthSample>, bank: f64) {
        let sc = &self.scenario;
        let model = &self.draw.model;
        let x = self.propagator.state();
        let t = self.propagator.steps() as f64 * self.propagator.dt();
        let sample = sample.unwrap_or_else(|| truth_sample(sc, &self.draw, t, x, bank));
        let kin = kinematics(model, x, t);
        let beacons = sc.beacon_states(t);
        let mut triad = None;
        let sensed_accel = [0u8, 1, 2].map(|a| {
            sc.measurement.evaluate_sharing_triad(
                model,
                x,
                &kin,
                bank,
                &beacons,
                Channel::Accel(a),
                &mut triad,
            )
        });
        self.outputs = TruthOutputs {
            sample,
            sensed_accel,
            ranges: beacons.iter().map(|(p, _)| range(&kin.pos, p)).collect(),
            range_rates: beacons
                .iter()
                .map(|(p, v)| range_rate(&kin.pos, &kin.vel, p, v))
                .collect(),
        };
    }

    /// The engine's truth step: one RK4 step at `bank`, and the measurement epoch if a channel
    /// is due (`on_epoch` sees it with the truth sample at its time). Returns whether a step was
    /// taken and the epoch's sample, if any.
    fn truth_step(
        &mut self,
        bank: f64,
        beacon_available: &[bool],
        on_epoch: &mut impl FnMut(&MeasurementEpoch, &TruthSample),
        every_step: Option<&mut dyn FnMut(&TruthSample)>,
    ) -> Result<Option<Option<TruthSample>>, SimError> {
        let Some(step) = self.next_step(bank)? else {
            return Ok(None);
        };
        let model = &self.draw.model;
        let k = step.k;
        let due = self.periods.iter().any(|p| k % p == 0);
        let sc = &self.scenario;
        let sample = (due || every_step.is_some())
            .then(|| truth_sample(sc, &self.draw, step.t, &step.x, bank));
        if let (Some(f), Some(s)) = (every_step, &sample) {
            f(s);
        }
        let Some(s) = sample.filter(|_| due) else {
            return Ok(Some(None));
        };
        let periods = &self.periods;
        let truth = TruthAtEpoch {
            model,
            x: &step.x,
            kin: &step.kin,
            t: step.t,
            bank,
        };
        let schedule = EpochSchedule {
            due: |c: usize| k % periods[c] == 0,
            visible: &s.visible,
            commanded: |i: usize| beacon_available.get(i).copied().unwrap_or(true),
        };
        let epoch = measure_epoch(sc, &truth, &schedule, &mut self.rng, &mut self.held);
        on_epoch(&epoch, &s);
        self.last_epoch = Some(epoch);
        Ok(Some(Some(s)))
    }

    /// Advance from `t` by `h` with bank angle `bank` \[rad\] and beacon availability
    /// `beacon_available[i]` (missing entries count as available). `on_epoch` sees every
    /// measurement epoch with the truth sample at its time, in order.
    pub fn do_step_with(
        &mut self,
        t: f64,
        h: f64,
        bank: f64,
        beacon_available: &[bool],
        mut on_epoch: impl FnMut(&MeasurementEpoch, &TruthSample),
    ) -> Result<StepReport, EngineError> {
        check_step(self.time, t, h)?;
        if !bank.is_finite() {
            return Err(EngineError::NonFiniteInput("bank angle"));
        }
        let t_end = t + h;
        let dt = self.propagator.dt();
        let k_end = ((t_end / dt) + 1e-7).floor().max(0.0) as usize;
        let k_end = k_end.min(self.propagator.max_steps());
        let mut report = StepReport::default();
        self.last_epoch = None;
        let mut last_sample = None;
        while self.propagator.steps() < k_end {
            let Some(sample) = self.truth_step(bank, beacon_available, &mut on_epoch, None)? else {
                break;
            };
            report.truth_steps += 1;
            if sample.is_some() {
                report.epochs += 1;
            }
            last_sample = sample;
        }
        self.time = t_end;
        if report.truth_steps > 0 {
            self.refresh_outputs(last_sample, bank);
        }
        Ok(report)
    }

    /// [`TruthSensors::do_step_with`] without an epoch callback.
    pub fn do_step(
        &mut self,
        t: f64,
        h: f64,
        bank: f64,
        beacon_available: &[bool],
    ) -> Result<StepReport, EngineError> {
        self.do_step_with(t, h, bank, beacon_available, |_, _| {})
    }

    /// Run the truth to its end at the scenario's bank with every beacon available (the batch
    /// run: [`super::super::simulate_truth`]). `on_epoch` sees every epoch with its sample;
    /// returns whether the last integration step produced an epoch.
    pub fn run_to_end(
        &mut self,
        on_epoch: impl FnMut(&MeasurementEpoch, &TruthSample),
    ) -> Result<bool, SimError> {
        self.run_to_end_seeing_steps(on_epoch, None::<fn(&TruthSample)>)
    }

    /// [`TruthSensors::run_to_end`], handing the truth sample of every integration step (not
    /// only of the epochs) to `every_step` when given (e.g. for the peak loads of `simulate`).
    pub fn run_to_end_seeing_steps(
        &mut self,
        mut on_epoch: impl FnMut(&MeasurementEpoch, &TruthSample),
        mut every_step: Option<impl FnMut(&TruthSample)>,
    ) -> Result<bool, SimError> {
        let bank = self.scenario.truth_bank;
        let mut last_sample = None;
        let mut stepped = false;
        while let Some(sample) = self.truth_step(
            bank,
            &[],
            &mut on_epoch,
            every_step
                .as_mut()
                .map(|f| f as &mut dyn FnMut(&TruthSample)),
        )? {
            stepped = true;
            last_sample = sample;
        }
        let ended_on_epoch = last_sample.is_some();
        self.time = self.propagator.steps() as f64 * self.propagator.dt();
        if stepped {
            self.refresh_outputs(last_sample, bank);
        }
        Ok(ended_on_epoch)
    }
}
