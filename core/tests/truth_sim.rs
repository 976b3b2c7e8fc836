//! Truth simulator behaviour users rely on: seeded reproducibility, noise statistics, outages,
//! visibility, and the sensor models' values.

use entrynav::scenario::{Scenario, ScenarioConfig, TruthDraw};
use entrynav::sensors::Channel;
use entrynav::sim::{TruthRun, simulate_truth};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;

fn scenario(name: &str) -> Scenario {
    Scenario::build(
        ScenarioConfig::builtin(name).unwrap(),
        &entrynav::files::no_files,
    )
    .unwrap()
}

fn nominal(s: &Scenario) -> TruthDraw {
    TruthDraw {
        initial: s.truth_initial,
        model: s.truth_model.clone(),
    }
}

fn run(s: &Scenario, seed: u64, dispersed: bool) -> TruthRun {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let d = if dispersed {
        s.draw_truth(&mut rng)
    } else {
        nominal(s)
    };
    simulate_truth(s, &d, &mut rng).unwrap()
}

#[test]
fn same_seed_same_run_different_seed_different_noise() {
    let s = scenario("msl-airdata");
    let a = run(&s, 7, true);
    let b = run(&s, 7, true);
    let c = run(&s, 8, true);
    assert_eq!(a.epochs, b.epochs);
    assert_eq!(a.samples, b.samples);
    assert_ne!(a.epochs[10].values, c.epochs[10].values);
    assert_ne!(
        a.samples.last().unwrap().density,
        c.samples.last().unwrap().density,
        "atmosphere is redrawn per seed"
    );
}

#[test]
fn measurement_noise_has_the_configured_sigma() {
    // Range noise on four-beacon-fusion: residual (measured - noiseless) std ≈ sqrt(20) m.
    let s = scenario("four-beacon-fusion");
    let mut res = Vec::new();
    for seed in 0..20 {
        let r = run(&s, seed, false);
        for (e, smp) in r.epochs.iter().zip(&r.samples[1..]) {
            assert!((e.t - smp.t).abs() < 1e-12);
            let x = nalgebra::SVector::<f64, 6>::from(smp.state);
            let beacons = s.beacon_states(e.t);
            let c = s
                .channels
                .iter()
                .position(|c| c.channel == Channel::Range(0))
                .unwrap();
            let truth =
                s.measurement
                    .evaluate(&s.truth_model, &x, e.t, 0.0, &beacons, Channel::Range(0));
            res.push(e.values[c].unwrap() - truth);
        }
    }
    let n = res.len() as f64;
    let mean = res.iter().sum::<f64>() / n;
    let sd = (res.iter().map(|r| (r - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt();
    assert!((sd / 20f64.sqrt() - 1.0).abs() < 0.05, "sample sigma {sd}");
    assert!(mean.abs() < 4.0 * sd / n.sqrt(), "mean {mean}");
}

#[test]
fn outage_removes_only_the_failed_beacon_and_keeps_other_noise() {
    let ok = scenario("four-beacon-fusion");
    let fault = scenario("four-beacon-fusion-fault");
    let a = run(&ok, 3, false);
    let b = run(&fault, 3, false);
    let c_o2 = fault
        .channels
        .iter()
        .position(|c| c.channel == Channel::Range(3))
        .unwrap();
    for (ea, eb) in a.epochs.iter().zip(&b.epochs) {
        if eb.t >= 200.0 {
            assert!(
                eb.values[c_o2].is_none(),
                "orbiter-2 must be silent at t = {}",
                eb.t
            );
        } else {
            assert!(eb.values[c_o2].is_some());
        }
        for (c, (va, vb)) in ea.values.iter().zip(&eb.values).enumerate() {
            if c != c_o2 {
                assert_eq!(va, vb, "channel {c} changed at t = {}", ea.t);
            }
        }
    }
}

#[test]
fn far_side_beacons_give_nothing_when_visibility_is_checked() {
    let mut cfg = ScenarioConfig::builtin("four-beacon-fusion").unwrap();
    cfg.ignore_visibility = false;
    let s = Scenario::build(cfg, &entrynav::files::no_files).unwrap();
    let r = run(&s, 1, false);
    let radio: Vec<usize> = s
        .channels
        .iter()
        .enumerate()
        .filter(|(_, c)| c.channel.beacon().is_some())
        .map(|(i, _)| i)
        .collect();
    let first = &r.epochs[0];
    assert!(
        radio.iter().all(|&c| first.values[c].is_none()),
        "seed 000's beacons start below the horizon"
    );
    assert!(first.values[0].is_some(), "the IMU is unaffected");
}

#[test]
fn accelerometer_reads_drag_plus_bias() {
    // Velocity-frame IMU, bank 0: accel_x = -D + bias, accel_y = bias, accel_z = L + bias.
    let s = scenario("four-beacon-fusion");
    let r = run(&s, 11, false);
    let i = r.epochs.len() / 3;
    let (e, smp) = (&r.epochs[i], &r.samples[i + 1]);
    let d = smp.aero_accel / (1.0 + 0.156f64 * 0.156).sqrt();
    let ax = e.values[0].unwrap();
    let az = e.values[2].unwrap();
    assert!((ax - (-d - 0.03)).abs() < 6e-3, "ax {ax} vs {}", -d - 0.03);
    assert!((az - (0.156 * d - 0.03)).abs() < 6e-3, "az {az}");
    // Dynamic pressure is consistent with density and speed.
    assert!(
        (smp.dynamic_pressure - 0.5 * smp.density * smp.spherical[3].powi(2)).abs()
            < 1e-9 * smp.dynamic_pressure
    );
}

#[test]
fn stop_speed_trigger_ends_the_run() {
    let s = scenario("msl-pressure");
    let r = run(&s, 1, false);
    let last = r.samples.last().unwrap();
    assert_eq!(r.stop, entrynav::sim::StopReason::StopSpeed);
    assert!(last.spherical[3] < 450.0 && last.t < 400.0);
}
