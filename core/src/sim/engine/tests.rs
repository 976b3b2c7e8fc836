//! The engine's step-wise and batch paths agree bit for bit.

use super::record::simulate_truth;
use super::run_seed::run_seed;
use super::start::initial_estimate;
use super::*;
use crate::estimation::nav::FilterKind;
use crate::files::no_files;
use crate::scenario::{Scenario, ScenarioConfig};
use crate::sensors::MeasurementEpoch;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;

fn scenario(name: &str) -> Arc<Scenario> {
    let cfg = ScenarioConfig::builtin(name).unwrap();
    Arc::new(Scenario::build(cfg, &no_files).unwrap())
}

#[test]
fn truth_on_any_communication_grid_matches_simulate_truth_bitwise() {
    for name in ["four-beacon-fusion-fault", "msl-airdata"] {
        let sc = scenario(name);
        let seed = 11;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let draw = sc.draw_truth(&mut rng);
        let run = simulate_truth(&sc, &draw, &mut rng).unwrap();
        let mut ts = TruthSensors::new(Arc::clone(&sc), seed, true);
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
        assert_eq!(ts.stop(), Some(run.stop), "{name}");
    }
}

/// The combined co-simulation (truth and filter stepped together, as the FMU does) equals the
/// batch path of the Monte Carlo (the truth recorded first, then the filter over its epochs).
#[test]
fn combined_engine_matches_the_batch_path_bitwise() {
    let sc = scenario("four-beacon-fusion");
    let seed = run_seed(3, 0);
    for kind in [FilterKind::Dcifaif, FilterKind::Ekf, FilterKind::Ukf] {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        let draw = sc.draw_truth(&mut rng);
        let run = simulate_truth(&sc, &draw, &mut rng).unwrap();
        let x0 = initial_estimate(&sc, &draw, &run.samples[0], &mut rng);
        let mut batch = Navigator::new(Arc::clone(&sc.onboard), kind, &x0).unwrap();
        let mut co = EntryCoSim::new(Arc::clone(&sc), kind, seed, true).unwrap();
        for (k, (epoch, sample)) in run.epochs_with_truth().enumerate() {
            assert!(batch.process(epoch));
            let judged = batch.judge(&sc, &draw, sample);
            co.do_step(k as f64, 1.0, sc.truth_bank, &[true; 4])
                .unwrap();
            assert_eq!(
                co.nav().estimate(),
                batch.estimate(),
                "{kind} at {}",
                epoch.t
            );
            assert_eq!(*co.judgement(), judged, "{kind} at {}", epoch.t);
            assert!(judged.nees.is_some());
        }
        assert_eq!(co.nav().status().code(), 1);
    }
}

#[test]
fn split_pair_reproduces_combined() {
    let sc = scenario("msl-pressure-orbiter");
    let seed = 5;
    let kind = FilterKind::MmaeMoe;
    let mut co = EntryCoSim::new(Arc::clone(&sc), kind, seed, true).unwrap();
    let mut truth = TruthSensors::new(Arc::clone(&sc), seed, true);
    let mut nav = Navigator::for_seed(&sc, kind, seed, true).unwrap();
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

/// A commanded bank other than the scenario's reaches the filter: the combined engine equals a
/// filter fed the recorded epochs and told that bank, and its final position error is far below
/// that of the old behaviour (the filter left at the scenario's bank).
#[test]
fn commanded_bank_reaches_the_filter() {
    let sc = scenario("msl-pressure");
    assert_eq!(sc.truth_bank, 0.0);
    let bank = 50f64.to_radians();
    let mut cfg = sc.config.clone();
    cfg.truth.bank_deg = 50.0;
    let flown = Arc::new(Scenario::build(cfg, &no_files).unwrap());
    let seed = run_seed(2, 0);
    let kind = FilterKind::Ekf;
    // The truth flown at `bank` throughout, and the filter run over its epochs.
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let draw = flown.draw_truth(&mut rng);
    let run = simulate_truth(&flown, &draw, &mut rng).unwrap();
    let mut srng = ChaCha8Rng::seed_from_u64(seed);
    srng.set_stream(1);
    let x0 = initial_estimate(&sc, &draw, &run.samples[0], &mut srng);
    let final_step = |told: bool| {
        let mut nav = Navigator::new(Arc::clone(&sc.onboard), kind, &x0).unwrap();
        if told {
            nav.set_bank_angle(bank).unwrap();
        }
        let mut last = None;
        for (epoch, sample) in run.epochs_with_truth() {
            nav.process(epoch);
            last = Some((nav.estimate().clone(), nav.judge(&sc, &draw, sample)));
        }
        last.unwrap()
    };
    let ((told_est, told), (_, old)) = (final_step(true), final_step(false));
    let mut co = EntryCoSim::new(Arc::clone(&sc), kind, seed, true).unwrap();
    let mut k = 0;
    while co.truth().stop().is_none() {
        co.do_step(k as f64, 1.0, bank, &[]).unwrap();
        k += 1;
    }
    let est = co.nav().estimate();
    assert_eq!(*est, told_est);
    assert_eq!(co.judgement().err, told.err);
    let pos = |e: &[f64]| (e[0] * e[0] + e[1] * e[1] + e[2] * e[2]).sqrt();
    let (now, before) = (pos(&co.judgement().err), pos(&old.err));
    println!(
        "final position error: {now:.1} m (filter told the bank), {before:.1} m (left at the scenario bank)"
    );
    assert!(
        now * 10.0 < before,
        "final position error {now} m vs {before} m"
    );
    // The filter alone, given the same epochs and bank, is the same filter.
    let mut nav = Navigator::for_seed(&sc, kind, seed, true).unwrap();
    for (i, e) in run.epochs.iter().enumerate() {
        nav.do_step(i as f64, 1.0, bank, Some(e)).unwrap();
    }
    assert_eq!(nav.estimate(), est);
    assert!(matches!(
        nav.do_step(nav.time(), 1.0, f64::NAN, None),
        Err(EngineError::NonFiniteInput(_))
    ));
}

#[test]
fn step_errors() {
    let sc = scenario("four-beacon-fusion");
    let mut co = EntryCoSim::new(sc, FilterKind::Ci, 1, false).unwrap();
    assert!(matches!(
        co.do_step(1.0, 1.0, 0.0, &[]),
        Err(EngineError::CommunicationPoint { .. })
    ));
    assert!(matches!(
        co.do_step(0.0, 0.0, 0.0, &[]),
        Err(EngineError::StepSize(_))
    ));
    assert!(matches!(
        co.do_step(0.0, f64::NAN, 0.0, &[]),
        Err(EngineError::StepSize(_))
    ));
    assert!(matches!(
        co.do_step(0.0, 1.0, f64::INFINITY, &[]),
        Err(EngineError::NonFiniteInput(_))
    ));
    co.do_step(0.0, 1.0, 0.0, &[]).unwrap();
    assert_eq!(co.time(), 1.0);
    let bad = EntryCoSim::new(scenario("msl-pressure"), FilterKind::Ci, 1, false);
    assert!(matches!(bad, Err(EngineError::Nav(_))));
}

/// A bank that changes at every communication step (0.1 s against 1 Hz sensors, as in a
/// guidance loop) is flown by the filter piece by piece: the combined engine and a navigator fed
/// the truth's epochs one step late (the FMUs) both equal a filter predicted to each step start
/// with the bank before it; and that filter's position error is far below the one given each
/// interval's last bank for the whole prediction (the engine before the bank history).
#[test]
fn bank_changes_between_epochs_are_flown_piecewise() {
    let sc = scenario("four-beacon-fusion");
    let (kind, seed, h) = (FilterKind::Ekf, run_seed(5, 0), 0.1);
    let bank_at = |t: f64| 60f64.to_radians() * (2.0 * std::f64::consts::PI * t / 40.0).cos();
    // The truth's epochs, each with the index of the step that produced it.
    let mut ts = TruthSensors::new(Arc::clone(&sc), seed, true);
    let mut epochs: Vec<(usize, MeasurementEpoch, TruthSample)> = Vec::new();
    let mut k = 0;
    while ts.stop().is_none() && k < 2000 {
        ts.do_step_with(k as f64 * h, h, bank_at(k as f64 * h), &[], |e, s| {
            epochs.push((k, e.clone(), s.clone()))
        })
        .unwrap();
        k += 1;
    }
    let steps = k;
    assert!(epochs.len() > 150, "{} epochs", epochs.len());
    let x0 = Navigator::for_seed(&sc, kind, seed, true)
        .unwrap()
        .estimate()
        .x
        .clone();
    let onboard = sc.onboard.for_filter(kind);
    // The reference: the filter itself, switched at every step start (predicted there first when
    // `piecewise`), then stepped through the epochs of the step.
    let reference = |piecewise: bool| {
        let mut f = super::filter::build_erased(kind, &onboard, &x0).unwrap();
        let mut next = 0;
        let mut sq_err = 0.0;
        for k in 0..steps {
            let (t_k, b_k) = (k as f64 * h, bank_at(k as f64 * h));
            if piecewise && b_k != f.bank_angle() && t_k > f.time() + 1e-9 {
                f.predict_to(t_k).unwrap();
            }
            f.set_bank_angle(b_k);
            while next < epochs.len() && epochs[next].0 == k {
                let (_, e, s) = &epochs[next];
                f.step(e, &onboard.beacon_states(e.t)).unwrap();
                let j = f.judge(&sc, ts.draw(), s);
                sq_err += j.pos_vel_err.0.powi(2);
                next += 1;
            }
        }
        let rms = (sq_err / epochs.len() as f64).sqrt();
        (f.estimate(0.0, Default::default()).x, rms)
    };
    let ((x_ref, rms_now), (_, rms_before)) = (reference(true), reference(false));
    let mut co = EntryCoSim::new(Arc::clone(&sc), kind, seed, true).unwrap();
    for k in 0..steps {
        co.do_step(k as f64 * h, h, bank_at(k as f64 * h), &[])
            .unwrap();
    }
    assert_eq!(co.nav().estimate().x, x_ref, "combined engine");
    // The FMU wiring: each step the navigator gets the truth's newest epoch (measured before the
    // step) and the bank the truth flew over the previous step.
    let mut nav = Navigator::for_seed(&sc, kind, seed, true).unwrap();
    let mut next = 0;
    for k in 0..=steps {
        while next + 1 < epochs.len() && epochs[next + 1].0 < k {
            next += 1;
        }
        let newest = (epochs[next].0 < k).then(|| &epochs[next].1);
        let t_k = k as f64 * h;
        // Epochs the master would have delivered at earlier steps are never skipped here: every
        // step produces at most one (1 Hz against 0.1 s).
        let flown = bank_at(k.saturating_sub(1) as f64 * h);
        nav.do_step(t_k, h, flown, newest).unwrap();
    }
    assert_eq!(nav.estimate().x, x_ref, "navigator fed one step late");
    println!(
        "position RMS over epochs: {rms_now:.2} m piecewise, {rms_before:.2} m one bank per interval"
    );
    assert!(
        rms_now * 2.0 < rms_before,
        "piecewise {rms_now} m vs {rms_before} m"
    );
}
