//! [`TruthSensors`]: the truth trajectory and the measurement records, communication step by
//! communication step.

use super::*;
use crate::sim::truth::measure_epoch;

/// The truth realisation and the generator positioned for the measurement noise.
pub(super) fn truth_draw(
    scenario: &Scenario,
    seed: u64,
    dispersed: bool,
) -> (TruthDraw, ChaCha8Rng) {
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
    pub(super) outputs: TruthOutputs,
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
                let periods = &self.periods;
                let epoch = measure_epoch(
                    &sc,
                    model,
                    &x,
                    &kin,
                    tk,
                    bank,
                    |c| k % periods[c] == 0,
                    &s.visible,
                    |i| beacon_available.get(i).copied().unwrap_or(true),
                    &mut self.rng,
                );
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
