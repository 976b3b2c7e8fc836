//! Step-wise co-simulation engine: the entry dynamics, sensors and a navigation filter advanced
//! communication step by communication step, as an FMI co-simulation slave does (no I/O here; the
//! `fmu` crate wraps these types behind the FMI 2.0 C API).
//!
//! Three pieces:
//! - [`TruthSensors`]: the truth trajectory (fixed-step RK4 at `timing.truth_step_s`) and the
//!   measurement records, generated exactly like [`simulate_truth`](super::simulate_truth): a
//!   channel of period P is sampled at t = P, 2P, …, a noise value is drawn for every scheduled
//!   sample in channel order whether or not the sample is available, and a radio sample is
//!   available when its beacon is commanded available, is not in an outage and (unless the
//!   scenario ignores visibility) is above the horizon. The bank angle is an input, held constant
//!   over a communication step.
//! - [`NavigationCoSim`]: a navigation filter alone, fed with measurement epochs (values and
//!   validity flags); it predicts to each epoch and updates, as [`run_filter`](super::run_filter).
//! - [`EntryCoSim`]: both together, the filter run at every measurement epoch of the truth, with
//!   the estimate judged against the truth (error, NEES).
//!
//! Randomness: the truth generator is `ChaCha8Rng::seed_from_u64(seed)`, used for the dispersions
//! (when `dispersed`) and then for the measurement noise, as `entrynav simulate --seed` does; the
//! filter start (when `filter.sample_initial_from_p0`) is drawn from the same seed's ChaCha stream
//! 1, so it does not depend on how long the truth runs. With constant inputs (bank angle of the
//! scenario, every beacon available) the engine therefore reproduces `simulate_truth` bit for bit,
//! and with a fixed filter start it reproduces Monte Carlo run `r` of `trade --seed S` for
//! `seed = run_seed(S, r)`, `dispersed = true`.
//!
//! Bank angle: the commanded bank is known onboard, so the filter's onboard dynamics and
//! measurement models use it too ([`NavFilter::set_bank_angle`]). [`EntryCoSim::do_step`] gives the
//! step's bank to both the truth and the filter, and [`NavigationCoSim::do_step`] takes it as an
//! input; the filter starts with the scenario's bank (`truth.bank_deg`) and uses the bank of a step
//! for every epoch that step processes (the prediction from the previous epoch included). When
//! the measurement epochs fall on communication points (a communication step that is a multiple
//! of the sensor periods) the filter's bank history is therefore exactly the truth's. A
//! [`NavigationCoSim`] fed the epochs of a separate [`TruthSensors`] one step late should get the
//! bank of the step those epochs were measured in (the command delayed by the same step).
//!
//! Everything is deterministic: the same parameters and the same sequence of `do_step` calls give
//! bit-identical outputs, which is what the FMU's state serialisation (a replay log) relies on.

use super::navigation::NavStep;
use super::truth::{MeasurementEpoch, SimError, StopReason, TruthSample};
use crate::dynamics::aero::drag_lift;
use crate::estimation::EstimationError;
use crate::estimation::nav::setup::estimation_error;
use crate::estimation::nav::{
    FilterKind, NavError, NavFilter, StepInfo, build_filter, filter_start, truth_in_filter_coords,
};
use crate::frames::inertial_to_spherical;
use crate::math::V3;
use crate::scenario::{Scenario, TruthDraw};
use crate::sensors::channels::kinematics;
use crate::sensors::{Channel, dynamic_pressure, range, range_rate, sutton_graves_heating};
use nalgebra::SVector;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};
use std::sync::Arc;
use thiserror::Error;

/// Largest filter state dimension.
pub const MAX_STATE_DIM: usize = 10;

/// Why a co-simulation step or set-up failed.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum CoSimError {
    /// The filter does not fit the scenario, or its dimension is unsupported.
    #[error(transparent)]
    Nav(#[from] NavError),
    /// The filter could not be built.
    #[error("cannot build the filter: {0}")]
    Filter(#[from] EstimationError),
    /// The truth became non-finite.
    #[error(transparent)]
    Truth(#[from] SimError),
    /// A step that does not start where the previous one ended.
    #[error("step starts at t = {got} s but the current communication point is t = {expected} s")]
    CommunicationPoint {
        /// Current time of the engine \[s\].
        expected: f64,
        /// Start time asked for \[s\].
        got: f64,
    },
    /// A step size that is not finite and positive.
    #[error("communication step size must be finite and > 0 (got {0})")]
    StepSize(f64),
    /// A non-finite input.
    #[error("input '{0}' is not finite")]
    NonFiniteInput(&'static str),
}

/// Whether two communication points are the same instant (relative tolerance 1e-9).
pub fn same_time(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1.0)
}

fn check_step(time: f64, t: f64, h: f64) -> Result<(), CoSimError> {
    if !t.is_finite() || !same_time(time, t) {
        return Err(CoSimError::CommunicationPoint {
            expected: time,
            got: t,
        });
    }
    if !(h.is_finite() && h > 0.0) {
        return Err(CoSimError::StepSize(h));
    }
    Ok(())
}

/// The truth realisation and the generator positioned for the measurement noise.
fn truth_draw(scenario: &Scenario, seed: u64, dispersed: bool) -> (TruthDraw, ChaCha8Rng) {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let draw = if dispersed {
        scenario.draw_truth(&mut rng)
    } else {
        TruthDraw {
            initial: scenario.truth_initial,
            model: scenario.truth_model.clone(),
        }
    };
    (draw, rng)
}

/// The truth sample at `t` (the same quantities as the truth simulator records).
pub fn truth_sample(
    scenario: &Scenario,
    draw: &TruthDraw,
    t: f64,
    x: &SVector<f64, 6>,
    bank: f64,
) -> TruthSample {
    let model = &draw.model;
    let kin = kinematics(model, x, t);
    let spherical = if model.kind.is_cartesian() {
        inertial_to_spherical(&kin.pos, &kin.vel, t, model.planet.rotation_rate)
    } else {
        [x[0], x[1], x[2], x[3], x[4], x[5]]
    };
    let p = model.aero_params(x, bank);
    let (d, l) = drag_lift(kin.density, kin.airspeed, &p);
    let h = scenario.measurement.heating;
    TruthSample {
        t,
        state: [x[0], x[1], x[2], x[3], x[4], x[5]],
        spherical,
        altitude: spherical[0] - model.planet.radius,
        density: kin.density,
        dynamic_pressure: dynamic_pressure(kin.density, kin.airspeed),
        heating: sutton_graves_heating(kin.density, kin.airspeed, h.k, h.nose_radius),
        aero_accel: (d * d + l * l).sqrt(),
        visible: scenario
            .beacons
            .iter()
            .map(|b| b.visible_from(kin.pos, t, model.planet.radius))
            .collect(),
    }
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
#[derive(Debug, Clone)]
pub struct TruthSensors {
    scenario: Arc<Scenario>,
    draw: TruthDraw,
    rng: ChaCha8Rng,
    x: SVector<f64, 6>,
    dt: f64,
    k: usize,
    n_steps: usize,
    periods: Vec<usize>,
    time: f64,
    stop: Option<StopReason>,
    outputs: TruthOutputs,
    last_epoch: Option<MeasurementEpoch>,
}

impl TruthSensors {
    /// Start at t = 0 from the truth realisation of `seed` (dispersed or nominal), with the
    /// scenario's bank angle for the initial outputs.
    pub fn new(scenario: Arc<Scenario>, seed: u64, dispersed: bool) -> TruthSensors {
        let (draw, rng) = truth_draw(&scenario, seed, dispersed);
        let timing = &scenario.config.timing;
        let dt = timing.truth_step_s;
        let n_steps = (timing.duration_s / dt).round().max(1.0) as usize;
        let periods = scenario
            .channels
            .iter()
            .map(|c| (c.period_s / dt).round().max(1.0) as usize)
            .collect();
        let x = draw.initial;
        let sample = truth_sample(&scenario, &draw, 0.0, &x, scenario.truth_bank);
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
            x,
            dt,
            k: 0,
            n_steps,
            periods,
            time: 0.0,
            stop: None,
            last_epoch: None,
        };
        let bank = out.scenario.truth_bank;
        out.refresh_outputs(None, bank);
        out
    }

    /// The scenario.
    pub fn scenario(&self) -> &Arc<Scenario> {
        &self.scenario
    }

    /// The truth realisation.
    pub fn draw(&self) -> &TruthDraw {
        &self.draw
    }

    /// Current communication point \[s\].
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Why the truth stopped (ground, stop speed, duration), if it has.
    pub fn stop(&self) -> Option<StopReason> {
        self.stop
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
        let t = self.k as f64 * self.dt;
        let sample = sample.unwrap_or_else(|| truth_sample(sc, &self.draw, t, &self.x, bank));
        let kin = kinematics(model, &self.x, t);
        let beacons = sc.beacon_states(t);
        let sensed_accel = [0u8, 1, 2].map(|a| {
            sc.measurement
                .evaluate_with(model, &self.x, &kin, bank, &beacons, Channel::Accel(a))
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
    ) -> Result<StepReport, CoSimError> {
        check_step(self.time, t, h)?;
        if !bank.is_finite() {
            return Err(CoSimError::NonFiniteInput("bank angle"));
        }
        let t_end = t + h;
        let k_end = ((t_end / self.dt) + 1e-7).floor().max(0.0) as usize;
        let k_end = k_end.min(self.n_steps);
        let mut report = StepReport::default();
        self.last_epoch = None;
        let mut last_sample = None;
        let sc = Arc::clone(&self.scenario);
        while self.stop.is_none() && self.k < k_end {
            let k = self.k + 1;
            let model = &self.draw.model;
            let x = model.step(&self.x, bank, self.dt);
            let tk = k as f64 * self.dt;
            if x.iter().any(|v| !v.is_finite()) {
                return Err(SimError::NonFinite {
                    t_s: tk,
                    state: [x[0], x[1], x[2], x[3], x[4], x[5]],
                }
                .into());
            }
            self.x = x;
            self.k = k;
            report.truth_steps += 1;
            let kin = kinematics(model, &x, tk);
            let r = (kin.pos[0] * kin.pos[0] + kin.pos[1] * kin.pos[1] + kin.pos[2] * kin.pos[2])
                .sqrt();
            let ground = r - model.planet.radius <= 0.0;
            let slow = sc
                .config
                .timing
                .stop_speed_mps
                .is_some_and(|v| kin.airspeed < v);
            let any_due = self.periods.iter().any(|p| k % p == 0);
            if any_due {
                let s = truth_sample(&sc, &self.draw, tk, &x, bank);
                let beacon_states = sc.beacon_states(tk);
                let mut values = Vec::with_capacity(sc.channels.len());
                for (c, spec) in sc.channels.iter().enumerate() {
                    if k % self.periods[c] != 0 {
                        values.push(None);
                        continue;
                    }
                    let truth = sc.measurement.evaluate_with(
                        model,
                        &x,
                        &kin,
                        bank,
                        &beacon_states,
                        spec.channel,
                    );
                    let z: f64 = StandardNormal.sample(&mut self.rng);
                    let available = match spec.channel.beacon() {
                        Some(i) => {
                            let cfg = &sc.config.beacons[i];
                            beacon_available.get(i).copied().unwrap_or(true)
                                && !cfg.in_outage(tk)
                                && (sc.config.ignore_visibility || s.visible[i])
                        }
                        None => true,
                    };
                    values.push(available.then(|| truth + spec.bias + spec.noise.sigma(truth) * z));
                }
                let epoch = MeasurementEpoch { t: tk, values };
                on_epoch(&epoch, &s);
                report.epochs += 1;
                self.last_epoch = Some(epoch);
                last_sample = Some(s);
            } else {
                last_sample = None;
            }
            if ground {
                self.stop = Some(StopReason::Ground);
            } else if slow {
                self.stop = Some(StopReason::StopSpeed);
            } else if k == self.n_steps {
                self.stop = Some(StopReason::Duration);
            }
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
    ) -> Result<StepReport, CoSimError> {
        self.do_step_with(t, h, bank, beacon_available, |_, _| {})
    }
}

/// A filter estimate at one epoch.
#[derive(Debug, Clone, PartialEq)]
pub struct NavEstimate {
    /// Epoch time of the estimate \[s\] (0 before the first epoch).
    pub t: f64,
    /// Estimate x̂ (filter-model coordinates; N entries).
    pub x: Vec<f64>,
    /// 1σ per state (√P_ii).
    pub sigma: Vec<f64>,
    /// Covariance, row-major N×N.
    pub p: Vec<f64>,
    /// Filter's density estimate at its estimate, when it estimates density [kg/m³].
    pub density: Option<f64>,
    /// What the last update reported (default before the first epoch).
    pub info: StepInfo,
}

/// The estimate judged against the truth at its epoch.
#[derive(Debug, Clone, PartialEq)]
pub struct Judgement {
    /// Truth in filter coordinates (NaN where a state has no truth counterpart).
    pub truth: Vec<f64>,
    /// Estimation error x̂ − x (angles wrapped).
    pub err: Vec<f64>,
    /// NEES eᵀP⁻¹e over the states with a truth value, and its degrees of freedom.
    pub nees: Option<(f64, usize)>,
    /// True density at the epoch [kg/m³].
    pub density_true: f64,
}

/// Filter health.
#[derive(Debug, Clone, PartialEq)]
pub enum NavStatus {
    /// No measurement epoch processed yet (the estimate is the filter start).
    Initial,
    /// Processing epochs.
    Running,
    /// Stopped on a numerical failure at `t`; the estimate holds its last good value.
    Failed {
        /// Epoch of the failure \[s\].
        t: f64,
        /// What failed.
        reason: String,
    },
}

impl NavStatus {
    /// Integer code: 0 initial, 1 running, 2 failed.
    pub fn code(&self) -> i32 {
        match self {
            NavStatus::Initial => 0,
            NavStatus::Running => 1,
            NavStatus::Failed { .. } => 2,
        }
    }
}

/// Object-safe view of a `NavFilter<N>` for N in 6..=10.
trait DynFilter: Send {
    fn set_bank_angle(&mut self, bank: f64);
    fn step(
        &mut self,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
    ) -> Result<StepInfo, String>;
    fn estimate(&self, t: f64, info: StepInfo) -> NavEstimate;
    fn judge(&self, scenario: &Scenario, draw: &TruthDraw, sample: &TruthSample) -> Judgement;
}

struct Dim<const N: usize>(Box<dyn NavFilter<N>>);

impl<const N: usize> DynFilter for Dim<N> {
    fn set_bank_angle(&mut self, bank: f64) {
        self.0.set_bank_angle(bank);
    }

    fn step(
        &mut self,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
    ) -> Result<StepInfo, String> {
        let info = self
            .0
            .predict(epoch.t)
            .and_then(|_| self.0.update(epoch, beacons))
            .map_err(|e| e.to_string())?;
        let (x, p) = self.0.estimate();
        if x.iter().chain(p.iter()).any(|v| !v.is_finite()) {
            return Err("estimate or covariance became non-finite".into());
        }
        Ok(info)
    }

    fn estimate(&self, t: f64, info: StepInfo) -> NavEstimate {
        let (x, p) = self.0.estimate();
        NavEstimate {
            t,
            x: x.iter().copied().collect(),
            sigma: (0..N).map(|i| p[(i, i)].max(0.0).sqrt()).collect(),
            p: (0..N)
                .flat_map(|i| (0..N).map(move |j| (i, j)))
                .map(|(i, j)| p[(i, j)])
                .collect(),
            density: self.0.density_estimate(),
            info,
        }
    }

    fn judge(&self, scenario: &Scenario, draw: &TruthDraw, sample: &TruthSample) -> Judgement {
        let (x, p) = self.0.estimate();
        let truth = truth_in_filter_coords::<N>(scenario, draw, sample);
        let err = estimation_error(scenario, &x, &truth);
        let step = NavStep {
            t: sample.t,
            x,
            p,
            truth,
            err,
            info: StepInfo::default(),
            density_est: None,
            density_profile_est: None,
            density_true: sample.density,
            truth_spherical: sample.spherical,
        };
        Judgement {
            truth: truth.iter().copied().collect(),
            err: err.iter().copied().collect(),
            nees: nees(&step),
            density_true: sample.density,
        }
    }
}

/// NEES eᵀP⁻¹e over the states that have a truth value (as the Monte Carlo metrics compute it).
fn nees<const N: usize>(step: &NavStep<N>) -> Option<(f64, usize)> {
    let idx: Vec<usize> = (0..N).filter(|&i| step.truth[i].is_finite()).collect();
    if idx.len() == N {
        let chol = step.p.cholesky()?;
        let v = chol.solve(&step.err);
        return Some((step.err.dot(&v), N));
    }
    let m = idx.len();
    if m == 0 {
        return None;
    }
    let p = nalgebra::DMatrix::from_fn(m, m, |a, b| step.p[(idx[a], idx[b])]);
    let e = nalgebra::DVector::from_fn(m, |a, _| step.err[idx[a]]);
    let chol = p.cholesky()?;
    Some((e.dot(&chol.solve(&e)), m))
}

fn make_filter<const N: usize>(
    kind: FilterKind,
    scenario: &Arc<Scenario>,
    draw: &TruthDraw,
    t0: &TruthSample,
    rng: &mut ChaCha8Rng,
) -> Result<Box<dyn DynFilter>, CoSimError> {
    let start = filter_start::<N>(scenario, draw, t0, rng);
    Ok(Box::new(Dim::<N>(build_filter::<N>(
        kind, scenario, &start,
    )?)))
}

/// A navigation filter alone, fed with measurement epochs.
pub struct NavigationCoSim {
    scenario: Arc<Scenario>,
    kind: FilterKind,
    filter: Box<dyn DynFilter>,
    estimate: NavEstimate,
    status: NavStatus,
    time: f64,
    last_epoch_t: f64,
}

impl std::fmt::Debug for NavigationCoSim {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("NavigationCoSim")
            .field("scenario", &self.scenario.config.name)
            .field("kind", &self.kind)
            .field("time", &self.time)
            .field("status", &self.status)
            .finish()
    }
}

impl NavigationCoSim {
    /// Filter `kind` on `scenario`, started as the combined engine starts it for `seed` and
    /// `dispersed` (the scenario's `filter.initial`, or with `filter.sample_initial_from_p0` a draw
    /// around the seed's truth realisation at t = 0 from the seed's stream 1).
    pub fn new(
        scenario: Arc<Scenario>,
        kind: FilterKind,
        seed: u64,
        dispersed: bool,
    ) -> Result<NavigationCoSim, CoSimError> {
        let (draw, _) = truth_draw(&scenario, seed, dispersed);
        let t0 = truth_sample(&scenario, &draw, 0.0, &draw.initial, scenario.truth_bank);
        Self::with_truth(scenario, kind, seed, &draw, &t0)
    }

    fn with_truth(
        scenario: Arc<Scenario>,
        kind: FilterKind,
        seed: u64,
        draw: &TruthDraw,
        t0: &TruthSample,
    ) -> Result<NavigationCoSim, CoSimError> {
        kind.check_fits(&scenario)?;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        rng.set_stream(1);
        let filter = match scenario.filter_model.state_dim() {
            6 => make_filter::<6>(kind, &scenario, draw, t0, &mut rng)?,
            7 => make_filter::<7>(kind, &scenario, draw, t0, &mut rng)?,
            8 => make_filter::<8>(kind, &scenario, draw, t0, &mut rng)?,
            9 => make_filter::<9>(kind, &scenario, draw, t0, &mut rng)?,
            10 => make_filter::<10>(kind, &scenario, draw, t0, &mut rng)?,
            other => return Err(NavError::Dimension(other).into()),
        };
        let estimate = filter.estimate(0.0, StepInfo::default());
        Ok(NavigationCoSim {
            scenario,
            kind,
            filter,
            estimate,
            status: NavStatus::Initial,
            time: 0.0,
            last_epoch_t: 0.0,
        })
    }

    /// The scenario.
    pub fn scenario(&self) -> &Arc<Scenario> {
        &self.scenario
    }

    /// The filter.
    pub fn kind(&self) -> FilterKind {
        self.kind
    }

    /// Filter state dimension.
    pub fn state_dim(&self) -> usize {
        self.estimate.x.len()
    }

    /// The latest estimate (at its epoch time `estimate().t`).
    pub fn estimate(&self) -> &NavEstimate {
        &self.estimate
    }

    /// Filter health.
    pub fn status(&self) -> &NavStatus {
        &self.status
    }

    /// Current communication point \[s\].
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Set the bank-angle command \[rad\] the filter's onboard models use from now on (the filter
    /// starts with the scenario's `truth.bank_deg`).
    pub fn set_bank_angle(&mut self, bank: f64) -> Result<(), CoSimError> {
        if !bank.is_finite() {
            return Err(CoSimError::NonFiniteInput("bank angle"));
        }
        self.filter.set_bank_angle(bank);
        Ok(())
    }

    /// Process one measurement epoch (predict to `epoch.t`, update). Epochs at or before the last
    /// processed one are ignored (a master holding its inputs over several steps), and so is every
    /// epoch after a filter failure. Returns whether the epoch was processed.
    pub fn process(&mut self, epoch: &MeasurementEpoch) -> bool {
        if matches!(self.status, NavStatus::Failed { .. })
            || epoch.t <= self.last_epoch_t
            || !epoch.t.is_finite()
        {
            return false;
        }
        self.last_epoch_t = epoch.t;
        let beacons = self.scenario.beacon_states(epoch.t);
        match self.filter.step(epoch, &beacons) {
            Ok(info) => {
                self.estimate = self.filter.estimate(epoch.t, info);
                self.status = NavStatus::Running;
            }
            Err(reason) => {
                self.status = NavStatus::Failed { t: epoch.t, reason };
            }
        }
        true
    }

    /// Advance from `t` by `h` with bank-angle command `bank` \[rad\], processing `epoch`
    /// (measurements taken at `epoch.t ≤ t + h`) if it is newer than the last one processed. The
    /// filter uses `bank` from this step on (prediction to the epoch included).
    pub fn do_step(
        &mut self,
        t: f64,
        h: f64,
        bank: f64,
        epoch: Option<&MeasurementEpoch>,
    ) -> Result<StepReport, CoSimError> {
        check_step(self.time, t, h)?;
        if !bank.is_finite() {
            return Err(CoSimError::NonFiniteInput("bank angle"));
        }
        let mut report = StepReport::default();
        if let Some(e) = epoch
            && e.values.iter().flatten().any(|v| !v.is_finite())
        {
            return Err(CoSimError::NonFiniteInput("measurement"));
        }
        self.filter.set_bank_angle(bank);
        if let Some(e) = epoch {
            if e.t <= t + h + 1e-9 && self.process(e) {
                report.epochs = 1;
            }
        }
        self.time = t + h;
        Ok(report)
    }

    fn judge(&self, draw: &TruthDraw, sample: &TruthSample) -> Judgement {
        self.filter.judge(&self.scenario, draw, sample)
    }
}

/// Truth, sensors and a navigation filter in one co-simulation slave.
#[derive(Debug)]
pub struct EntryCoSim {
    truth: TruthSensors,
    nav: NavigationCoSim,
    judgement: Judgement,
}

impl EntryCoSim {
    /// Filter `kind` on `scenario` with the truth realisation of `seed` (dispersed or nominal).
    pub fn new(
        scenario: Arc<Scenario>,
        kind: FilterKind,
        seed: u64,
        dispersed: bool,
    ) -> Result<EntryCoSim, CoSimError> {
        let truth = TruthSensors::new(Arc::clone(&scenario), seed, dispersed);
        let nav =
            NavigationCoSim::with_truth(scenario, kind, seed, truth.draw(), &truth.outputs.sample)?;
        let judgement = nav.judge(truth.draw(), &truth.outputs.sample);
        Ok(EntryCoSim {
            truth,
            nav,
            judgement,
        })
    }

    /// Advance from `t` by `h` with bank angle `bank` \[rad\] and beacon availability flags; the
    /// filter processes every measurement epoch of the step with its onboard models at `bank`.
    pub fn do_step(
        &mut self,
        t: f64,
        h: f64,
        bank: f64,
        beacon_available: &[bool],
    ) -> Result<StepReport, CoSimError> {
        check_step(self.nav.time, t, h)?;
        let mut epochs = Vec::new();
        let mut report =
            self.truth
                .do_step_with(t, h, bank, beacon_available, |epoch, sample| {
                    epochs.push((epoch.clone(), sample.clone()));
                })?;
        report.epochs = 0;
        self.nav.filter.set_bank_angle(bank);
        for (epoch, sample) in &epochs {
            if self.nav.process(epoch) {
                report.epochs += 1;
                if self.nav.status == NavStatus::Running {
                    self.judgement = self.nav.judge(self.truth.draw(), sample);
                }
            }
        }
        self.nav.time = t + h;
        Ok(report)
    }

    /// The truth and sensors.
    pub fn truth(&self) -> &TruthSensors {
        &self.truth
    }

    /// The filter.
    pub fn nav(&self) -> &NavigationCoSim {
        &self.nav
    }

    /// The latest estimate judged against the truth at its epoch.
    pub fn judgement(&self) -> &Judgement {
        &self.judgement
    }

    /// Current communication point \[s\].
    pub fn time(&self) -> f64 {
        self.nav.time
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::estimation::nav::{build_filter, filter_start};
    use crate::scenario::ScenarioConfig;
    use crate::sim::{run_filter, run_seed, simulate_truth};

    fn scenario(name: &str) -> Arc<Scenario> {
        let cfg = ScenarioConfig::builtin(name).unwrap();
        Arc::new(Scenario::build(cfg, &|p: &str| Err(format!("no file {p}"))).unwrap())
    }

    #[test]
    fn truth_matches_simulate_truth_bitwise() {
        for (name, dispersed) in [("four-beacon-fusion-fault", true), ("msl-airdata", true)] {
            let sc = scenario(name);
            let seed = 11;
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let draw = if dispersed {
                sc.draw_truth(&mut rng)
            } else {
                unreachable!()
            };
            let run = simulate_truth(&sc, &draw, &mut rng).unwrap();
            let mut ts = TruthSensors::new(Arc::clone(&sc), seed, dispersed);
            let mut epochs = Vec::new();
            let mut samples = Vec::new();
            // An irregular communication grid: the result must not depend on it.
            let mut t = 0.0;
            let mut i = 0;
            while ts.stop().is_none() {
                let h = [0.3, 1.0, 0.05, 2.5][i % 4];
                ts.do_step_with(t, h, sc.truth_bank, &[], |e, s| {
                    epochs.push(e.clone());
                    samples.push(s.clone());
                })
                .unwrap();
                t += h;
                i += 1;
            }
            assert_eq!(epochs, run.epochs, "{name}");
            assert_eq!(samples[..], run.samples[1..1 + samples.len()], "{name}");
            assert_eq!(ts.outputs().sample, *run.samples.last().unwrap(), "{name}");
        }
    }

    #[test]
    fn combined_matches_run_filter_bitwise() {
        let sc = scenario("four-beacon-fusion");
        let seed = run_seed(3, 0);
        for kind in [FilterKind::Dcifaif, FilterKind::Ekf] {
            let mut rng = ChaCha8Rng::seed_from_u64(seed);
            let draw = sc.draw_truth(&mut rng);
            let run = simulate_truth(&sc, &draw, &mut rng).unwrap();
            let start = filter_start::<8>(&sc, &draw, &run.samples[0], &mut rng);
            let mut filter = build_filter::<8>(kind, &sc, &start).unwrap();
            let mut steps = Vec::new();
            run_filter(&sc, &draw, &run, filter.as_mut(), |s| steps.push(s.clone()));
            let mut co = EntryCoSim::new(Arc::clone(&sc), kind, seed, true).unwrap();
            for (k, step) in steps.iter().enumerate() {
                co.do_step(k as f64, 1.0, 0.0, &[true; 4]).unwrap();
                let est = co.nav().estimate();
                assert_eq!(est.t, step.t);
                assert_eq!(est.x, step.x.iter().copied().collect::<Vec<_>>());
                assert_eq!(
                    est.p,
                    step.p.transpose().iter().copied().collect::<Vec<_>>()
                );
                assert_eq!(
                    co.judgement().err,
                    step.err.iter().copied().collect::<Vec<_>>()
                );
                assert_eq!(est.info, step.info);
                assert!(co.judgement().nees.is_some());
            }
        }
    }

    #[test]
    fn split_pair_reproduces_combined() {
        let sc = scenario("msl-pressure-orbiter");
        let seed = 5;
        let kind = FilterKind::MmaeMoe;
        let mut co = EntryCoSim::new(Arc::clone(&sc), kind, seed, true).unwrap();
        let mut truth = TruthSensors::new(Arc::clone(&sc), seed, true);
        let mut nav = NavigationCoSim::new(Arc::clone(&sc), kind, seed, true).unwrap();
        assert_eq!(nav.estimate(), co.nav().estimate());
        let h = 0.5;
        let mut pending: Option<MeasurementEpoch> = None;
        let mut previous = co.nav().estimate().clone();
        let mut processed = 0;
        for k in 0..200 {
            let t = k as f64 * h;
            let avail = [!(60..=90).contains(&k)];
            // The filter gets the measurements of the previous communication point, so after its
            // step it holds the combined engine's estimate of one step earlier.
            processed += nav.do_step(t, h, 0.1, pending.as_ref()).unwrap().epochs;
            assert_eq!(*nav.estimate(), previous, "step {k}");
            co.do_step(t, h, 0.1, &avail).unwrap();
            truth.do_step(t, h, 0.1, &avail).unwrap();
            pending = truth.last_epoch().cloned();
            previous = co.nav().estimate().clone();
        }
        assert_eq!(processed, 99);
        assert_eq!(co.nav().status().code(), 1);
    }

    /// A commanded bank other than the scenario's reaches the filter: the combined engine equals
    /// the in-process run of a filter told that bank, and its final position error is far below
    /// that of the old behaviour (the filter left at the scenario's bank).
    #[test]
    fn commanded_bank_reaches_the_filter() {
        let sc = scenario("msl-pressure");
        assert_eq!(sc.truth_bank, 0.0);
        let bank = 50f64.to_radians();
        let mut cfg = sc.config.clone();
        cfg.truth.bank_deg = 50.0;
        let flown = Arc::new(Scenario::build(cfg, &|p: &str| Err(format!("no file {p}"))).unwrap());
        let seed = run_seed(2, 0);
        let kind = FilterKind::Ekf;
        // The truth flown at `bank` throughout, and the filter run in process on it.
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let draw = flown.draw_truth(&mut rng);
        let run = simulate_truth(&flown, &draw, &mut rng).unwrap();
        let mut srng = ChaCha8Rng::seed_from_u64(seed);
        srng.set_stream(1);
        let start = filter_start::<6>(&sc, &draw, &run.samples[0], &mut srng);
        let final_step = |told: bool| {
            let mut f = build_filter::<6>(kind, &sc, &start).unwrap();
            if told {
                f.set_bank_angle(bank);
            }
            let mut last = None;
            run_filter(&sc, &draw, &run, f.as_mut(), |s| last = Some(s.clone()));
            last.unwrap()
        };
        let (told, old) = (final_step(true), final_step(false));
        let mut co = EntryCoSim::new(Arc::clone(&sc), kind, seed, true).unwrap();
        let mut k = 0;
        while co.truth().stop().is_none() {
            co.do_step(k as f64, 1.0, bank, &[]).unwrap();
            k += 1;
        }
        let est = co.nav().estimate();
        assert_eq!(est.t, told.t);
        assert_eq!(est.x, told.x.iter().copied().collect::<Vec<_>>());
        assert_eq!(
            co.judgement().err,
            told.err.iter().copied().collect::<Vec<_>>()
        );
        let pos = |e: &[f64]| (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
        let (now, before) = (pos(&co.judgement().err), pos(old.err.as_slice()));
        println!(
            "final position error: {now:.1} m (filter told the bank), {before:.1} m (left at the scenario bank)"
        );
        assert!(
            now * 10.0 < before,
            "final position error {now} m vs {before} m"
        );
        // The filter alone, given the same epochs and bank, is the same filter.
        let mut nav = NavigationCoSim::new(Arc::clone(&sc), kind, seed, true).unwrap();
        for (i, e) in run.epochs.iter().enumerate() {
            nav.do_step(i as f64, 1.0, bank, Some(e)).unwrap();
        }
        assert_eq!(nav.estimate(), est);
        assert!(matches!(
            nav.do_step(nav.time(), 1.0, f64::NAN, None),
            Err(CoSimError::NonFiniteInput(_))
        ));
    }

    #[test]
    fn step_errors() {
        let sc = scenario("four-beacon-fusion");
        let mut co = EntryCoSim::new(sc, FilterKind::Ci, 1, false).unwrap();
        assert!(matches!(
            co.do_step(1.0, 1.0, 0.0, &[]),
            Err(CoSimError::CommunicationPoint { .. })
        ));
        assert!(matches!(
            co.do_step(0.0, 0.0, 0.0, &[]),
            Err(CoSimError::StepSize(_))
        ));
        assert!(matches!(
            co.do_step(0.0, f64::NAN, 0.0, &[]),
            Err(CoSimError::StepSize(_))
        ));
        assert!(matches!(
            co.do_step(0.0, 1.0, f64::INFINITY, &[]),
            Err(CoSimError::NonFiniteInput(_))
        ));
        co.do_step(0.0, 1.0, 0.0, &[]).unwrap();
        assert_eq!(co.time(), 1.0);
        let bad = EntryCoSim::new(scenario("msl-pressure"), FilterKind::Ci, 1, false);
        assert!(matches!(bad, Err(CoSimError::Nav(_))));
    }
}
