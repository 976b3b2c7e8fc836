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

mod entry;
mod navigation;
mod truth_sensors;

pub use entry::EntryCoSim;
pub use navigation::{Judgement, NavEstimate, NavStatus, NavigationCoSim};
pub use truth_sensors::{StepReport, TruthOutputs, TruthSensors, truth_sample};

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

pub(super) fn check_step(time: f64, t: f64, h: f64) -> Result<(), CoSimError> {
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
