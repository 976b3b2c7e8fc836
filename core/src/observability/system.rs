//! The system whose observability is analysed, and the points along the truth trajectory where
//! it is analysed.
//!
//! **What system.** A scenario is analysed through its *filter* model: `ẋ = f(x)` is
//! [`EntryModel::rhs`] of `Scenario::filter_model` (n = 6 kinematic states plus the augmented
//! constants, whose derivative is zero) and `y = h(x)` stacks the scenario's measurement channels
//! ([`MeasurementModel::evaluate_sharing_triad`], one accelerometer triad for the three axes).
//! The bank angle is the truth's (0 in every paper scenario).
//!
//! **Time is frozen inside the derivatives.** Seed 002 (eq. 8) and seed 000 (eq. 10) analyse the
//! autonomous pair (f, h). At each analysis time t the measurement function is taken as
//! `h(x) = h(x, t)` with the beacons held at their positions and velocities at t; the Lie
//! derivatives then differentiate along f only. For surface beacons with a spherical
//! (planet-relative) state this is exact — range and range-rate to a beacon fixed on the planet
//! depend on the planet-relative state alone. For orbiters (and for surface beacons with the
//! Cartesian inertial state) it neglects the beacon's own motion over the derivative, as the papers
//! do.
//!
//! **Which point.** The analysis point at time t is the nominal truth trajectory (the scenario's
//! truth initial state, truth model and bank, stepped by the simulation engine's
//! [`TruthPropagator`] at `timing.truth_step_s`, exactly as every truth run is) mapped into the filter model's coordinates (copied when
//! truth and filter use the same equations, otherwise through the inertial position and velocity).
//! Augmented states take the *truth's* values — L/D and C_D S/m of the truth vehicle, and ρ0 =
//! truth reference density × truth density factor when the truth atmosphere is exponential — and
//! the filter's initial augmented value where the truth has no such constant.

use super::error::ObservabilityError;
use crate::atmosphere::AtmosphereModel;
use crate::dynamics::{AugmentedParam, EntryModel};
use crate::frames::inertial_to_spherical;
use crate::math::Real;
use crate::scenario::Scenario;
use crate::sensors::channels::kinematics;
use crate::sensors::{Channel, MeasurementModel};
use crate::sim::engine::{SimError, StopReason, TruthPropagator};
use nalgebra::SVector;

/// An autonomous system `ẋ = f(x)`, `y = h(x)` with `N` states, written generically over
/// [`Real`] so it evaluates in `f64`, dual numbers and [`super::Jet`]s.
pub trait ObservedSystem<const N: usize> {
    /// Number of scalar outputs m.
    fn outputs(&self) -> usize;
    /// The vector field f(x).
    fn f<T: Real>(&self, x: &SVector<T, N>) -> SVector<T, N>;
    /// The outputs h(x), written into `out` (length [`ObservedSystem::outputs`]).
    fn h<T: Real>(&self, x: &SVector<T, N>, out: &mut [T]);
}

/// A scenario's filter model and a subset of its channels, frozen at time `t`.
#[derive(Debug, Clone)]
pub struct ScenarioSystem<'a> {
    /// Dynamics (the scenario's filter model).
    pub model: &'a EntryModel<AtmosphereModel>,
    /// Deterministic measurement model.
    pub measurement: &'a MeasurementModel,
    /// The channels stacked into h, in this order.
    pub channels: Vec<Channel>,
    /// Inertial (position \[m\], velocity [m/s]) of every beacon at `t`, held constant.
    pub beacons: Vec<([f64; 3], [f64; 3])>,
    /// Analysis time \[s\] (enters the planet-rotation angle of the kinematics).
    pub t: f64,
    /// Bank angle \[rad\].
    pub bank: f64,
}

impl<const N: usize> ObservedSystem<N> for ScenarioSystem<'_> {
    fn outputs(&self) -> usize {
        self.channels.len()
    }

    fn f<T: Real>(&self, x: &SVector<T, N>) -> SVector<T, N> {
        self.model.rhs(x, self.bank)
    }

    fn h<T: Real>(&self, x: &SVector<T, N>, out: &mut [T]) {
        let kin = kinematics(self.model, x, self.t);
        let mut triad = None;
        for (o, &c) in out.iter_mut().zip(&self.channels) {
            *o = self.measurement.evaluate_sharing_triad(
                self.model,
                x,
                &kin,
                self.bank,
                &self.beacons,
                c,
                &mut triad,
            );
        }
    }
}

/// One analysis point on the nominal truth trajectory.
#[derive(Debug, Clone, PartialEq)]
pub struct AnalysisPoint {
    /// Time \[s\].
    pub t: f64,
    /// State in the filter model's coordinates (n = 6 + augmented entries).
    pub state: Vec<f64>,
    /// Vehicle inertial position \[m\].
    pub position: [f64; 3],
    /// Vehicle inertial velocity [m/s].
    pub velocity: [f64; 3],
    /// Inertial (position \[m\], velocity [m/s]) of every beacon at `t`.
    pub beacons: Vec<([f64; 3], [f64; 3])>,
    /// Per beacon: measurements available at `t` (not in an outage, and in line of sight unless
    /// the scenario ignores visibility) — the same rule as the truth simulator.
    pub available: Vec<bool>,
}

/// The analysis points every `step_s` seconds (rounded to a whole number of truth steps, at least
/// one) from t = 0 to the end of the nominal truth run (its duration, ground impact or the stop
/// speed, whichever comes first).
pub fn analysis_points(
    scenario: &Scenario,
    step_s: f64,
) -> Result<Vec<AnalysisPoint>, ObservabilityError> {
    if !(step_s.is_finite() && step_s > 0.0) {
        return Err(ObservabilityError::InvalidInput(format!(
            "analysis step must be a positive number of seconds, got {step_s}"
        )));
    }
    let h = scenario.config.timing.truth_step_s;
    let stride = ((step_s / h).round() as usize).max(1);
    let mut truth = TruthPropagator::for_scenario(scenario, scenario.truth_initial);
    let mut out = vec![analysis_point(scenario, 0.0, truth.state())];
    loop {
        let step = match truth.step(&scenario.truth_model, scenario.truth_bank) {
            Ok(Some(step)) => step,
            Ok(None) => break,
            Err(SimError::NonFinite { t_s, .. }) => {
                return Err(ObservabilityError::InvalidInput(format!(
                    "the nominal truth state became non-finite at t = {t_s} s"
                )));
            }
        };
        let early = matches!(
            step.stop,
            Some(StopReason::Ground) | Some(StopReason::StopSpeed)
        );
        if step.k % stride == 0 || early {
            out.push(analysis_point(scenario, step.t, &step.x));
        }
    }
    Ok(out)
}

fn analysis_point(scenario: &Scenario, t: f64, x: &SVector<f64, 6>) -> AnalysisPoint {
    let truth = &scenario.truth_model;
    let filter = scenario.filter_model();
    let kin = kinematics(truth, x, t);
    let kinematic: [f64; 6] = if truth.kind == filter.kind {
        [x[0], x[1], x[2], x[3], x[4], x[5]]
    } else if filter.kind.is_cartesian() {
        let (p, v) = (kin.pos, kin.vel);
        [p[0], p[1], p[2], v[0], v[1], v[2]]
    } else {
        inertial_to_spherical(&kin.pos, &kin.vel, t, filter.omega())
    };
    let mut state = kinematic.to_vec();
    for (k, a) in filter.augmented.iter().enumerate() {
        let fallback = scenario
            .onboard
            .initial_estimate
            .get(6 + k)
            .copied()
            .unwrap_or(0.0);
        let draw = scenario.nominal_truth();
        state.push(match a {
            AugmentedParam::Rho0 => match scenario.config.truth.atmosphere.reference_density() {
                Some(_) => truth.rho0_model * truth.density_factor,
                None => fallback,
            },
            _ => scenario.truth_parameter(&draw, *a).unwrap_or(fallback),
        });
    }
    let radius = truth.planet.radius;
    let available = scenario
        .beacons
        .iter()
        .zip(&scenario.config.beacons)
        .map(|(b, cfg)| {
            !cfg.in_outage(t)
                && (scenario.config.ignore_visibility || b.visible_from(kin.pos, t, radius))
        })
        .collect();
    AnalysisPoint {
        t,
        state,
        position: kin.pos,
        velocity: kin.vel,
        beacons: scenario.beacon_states(t).into_owned(),
        available,
    }
}
