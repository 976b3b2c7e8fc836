//! `MarsEntryGuidance` through the C API: it reproduces the in-process guided loop
//! (`entrynav::sim::guided_run`) bit for bit on the same inputs, refuses a scenario without
//! `[guidance]`, checks every input, and gives the same bank whatever the communication grid.

mod common;

use common::Inst;
use entrynav::estimation::nav::FilterKind;
use entrynav::sim::guided::{GuidedStep, fly_with_filter_recorded};
use entrynav_fmu::vars::guided_scenario_toml;
use entrynav_fmu::vars::{GUIDED_SCENARIO_FILE, Key, MAX_STATES, Model, Slot, guided_scenario};
use std::path::PathBuf;
use std::sync::Arc;

/// A resources folder holding the guided scenario, as `entrynav fmu pack` ships it.
fn resources(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!(
        "entrynav-guidance-fmu-{tag}-{}",
        std::process::id()
    ));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join(GUIDED_SCENARIO_FILE), guided_scenario_toml()).unwrap();
    dir
}

fn guidance(tag: &str) -> Inst {
    let dir = resources(tag);
    Inst::with(Model::Guidance, Some(dir.to_str().unwrap()), false)
}

/// Set the inputs a recorded step of the in-process loop gave its guidance.
fn set_inputs(i: &Inst, s: &GuidedStep) {
    for k in 0..MAX_STATES {
        let x = s.est_x.get(k).copied().unwrap_or(0.0);
        assert_eq!(i.set_real(Key::EstX(k), x), 0, "{}", i.last());
    }
    for k in 0..6 {
        assert_eq!(
            i.set_real(Key::EstSigma(k), s.est_sigma[k]),
            0,
            "{}",
            i.last()
        );
    }
    assert_eq!(i.set_real(Key::NavTime, s.est_t), 0);
    assert_eq!(i.set_int(Key::NavStatusCode, s.nav_status), 0);
    for k in 0..3u8 {
        let a = s.accel.map(|a| a[k as usize]);
        assert_eq!(i.set_real(Key::Meas(Slot::Accel(k)), a.unwrap_or(0.0)), 0);
        assert_eq!(i.set_bool(Key::MeasValid(Slot::Accel(k)), a.is_some()), 0);
    }
}

/// One guided run of the core with the EKF in the loop, every step recorded.
fn core_run(seed: u64) -> (Vec<GuidedStep>, f64) {
    let scenario = Arc::new(guided_scenario().unwrap());
    let dt = scenario.config.timing.truth_step_s;
    let mut steps = Vec::new();
    fly_with_filter_recorded(&scenario, FilterKind::Ekf, seed, 0, |s| {
        steps.push(s.clone())
    })
    .unwrap();
    (steps, dt)
}

#[test]
fn reproduces_the_in_process_guided_loop_bit_for_bit() {
    let (steps, dt) = core_run(28);
    let i = guidance("loop");
    assert_eq!(i.init(), [0, 0, 0], "{:?}", i.messages());
    let mut compared = 0;
    let mut cycles = 0;
    for s in &steps {
        set_inputs(&i, s);
        assert_eq!(i.step(s.t, dt), 0, "{:?}", i.messages());
        if i.boolean(Key::Deployed) {
            // The FMU judges deployment on the estimate; the core loop on the truth, which
            // the FMU never sees. From here the FMU holds its last command.
            break;
        }
        cycles += s.cycle as i32;
        assert_eq!(
            i.real(Key::GuidanceBank).to_bits(),
            s.bank.to_bits(),
            "bank at t = {}",
            s.t
        );
        assert_eq!(i.real(Key::GuidanceCommand).to_bits(), s.command.to_bits());
        assert_eq!(i.int(Key::GuidanceCycles), cycles);
        compared += 1;
    }
    eprintln!(
        "compared {compared} of {} steps ({cycles} cycles) bit for bit",
        steps.len()
    );
    // The estimate reaches the trigger within a few guidance periods of the truth.
    assert!(
        compared + 100 >= steps.len() && compared > 1000,
        "compared {compared} of {} steps",
        steps.len()
    );
    // Guidance moved the bank (reversals), within the rate limit at every step.
    let banks: Vec<f64> = steps.iter().map(|s| s.bank).collect();
    let (lo, hi) = banks
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), x| (a.min(*x), b.max(*x)));
    assert!(lo < 0.0 && hi > 0.0, "no reversal: bank in [{lo}, {hi}]");
    let rate = 20f64.to_radians();
    assert!(
        banks
            .windows(2)
            .all(|w| (w[1] - w[0]).abs() <= rate * dt * (1.0 + 1e-12))
    );
}

#[test]
fn after_the_trigger_on_the_estimate_the_bank_settles_and_holds() {
    let (steps, dt) = core_run(28);
    let i = guidance("deploy");
    assert_eq!(i.init(), [0, 0, 0]);
    // guidance_status: waiting before the first cycle, flying until the trigger, then deployed.
    assert_eq!(i.int(Key::GuidanceStatus), 0);
    let mut at = None;
    for s in &steps {
        set_inputs(&i, s);
        assert_eq!(i.step(s.t, dt), 0, "{:?}", i.messages());
        let status = i.int(Key::GuidanceStatus);
        assert_eq!(i.int(Key::GuidanceStatusCode), status);
        assert_eq!(status, if i.boolean(Key::Deployed) { 2 } else { 1 });
        if at.is_none() && i.boolean(Key::Deployed) {
            at = Some((
                s.t,
                i.int(Key::GuidanceCycles),
                i.real(Key::GuidanceCommand),
            ));
        }
    }
    // The in-process loop's last recorded step is the one on which it deployed, deciding the
    // range trigger (msl-guided's default) on the estimate at every truth step; the FMU decides
    // it at its guidance cycles (1 Hz), on the estimate carried to the cycle's time: hold the
    // last inputs for up to one guidance period.
    let last = steps.last().unwrap();
    let period = (1.0 / guided_scenario().unwrap().config.guidance.unwrap().rate_hz / dt).round();
    let mut t = last.t + dt;
    for _ in 0..period as usize {
        if at.is_some() {
            break;
        }
        assert_eq!(i.step(t, dt), 0, "{:?}", i.messages());
        if i.boolean(Key::Deployed) {
            at = Some((t, i.int(Key::GuidanceCycles), i.real(Key::GuidanceCommand)));
        }
        t += dt;
    }
    let (t_deploy, cycles, command) = at.expect("the estimate reached the deployment trigger");
    assert!(i.real(Key::DeployTrigger) <= 0.0);
    // No cycle after deployment: the command and the cycle count are frozen.
    assert_eq!(i.int(Key::GuidanceCycles), cycles);
    assert_eq!(i.real(Key::GuidanceCommand), command);
    // Keep stepping with the last inputs for 30 s: the actuator reaches the command and stays.
    for _ in 0..600 {
        assert_eq!(i.step(t, dt), 0);
        t += dt;
    }
    assert_eq!(i.real(Key::GuidanceBank), command);
    assert_eq!(i.real(Key::GuidanceBankRate), 0.0);
    eprintln!(
        "deployed on the estimate at t = {t_deploy} s after {cycles} cycles (the in-process loop at {} s)",
        last.t
    );
    assert!(t_deploy > 100.0, "deployed at {t_deploy} s");
}

#[test]
fn a_scenario_without_guidance_is_refused_at_initialisation() {
    let i = guidance("noguid");
    assert_eq!(i.set_string(Key::Scenario, "msl-airdata"), 0);
    assert_eq!(i.init()[2], 3);
    let msg = i.last();
    assert!(
        msg.contains("no [guidance] section") && msg.contains("msl-airdata"),
        "{msg}"
    );
    // The error state: only reset leads on.
    assert_eq!(i.step(0.0, 0.05), 3);
}

#[test]
fn every_input_is_checked_and_a_refused_step_changes_nothing() {
    let (steps, dt) = core_run(28);
    let i = guidance("inputs");
    assert_eq!(i.init(), [0, 0, 0]);
    set_inputs(&i, &steps[0]);
    // Non-finite and out-of-range values are refused when set.
    assert_eq!(i.set_real(Key::EstX(0), f64::NAN), 3);
    assert!(i.last().contains("not a finite number"), "{}", i.last());
    assert_eq!(i.set_real(Key::Meas(Slot::Accel(1)), f64::INFINITY), 3);
    assert_eq!(i.set_real(Key::EstSigma(2), -1.0), 3);
    assert!(i.last().contains(">= 0"), "{}", i.last());
    assert_eq!(i.set_int(Key::NavStatusCode, 3), 3);
    assert!(
        i.last().contains("not a filter status code"),
        "{}",
        i.last()
    );
    // An estimate guidance cannot fly (all zero) is refused at the step.
    let zero = GuidedStep {
        est_x: vec![0.0; 6],
        ..steps[0].clone()
    };
    set_inputs(&i, &zero);
    assert_eq!(i.step(0.0, dt), 3);
    assert!(
        i.last().contains("not a state guidance can fly"),
        "{}",
        i.last()
    );
    // A failed filter is refused too.
    let failed = GuidedStep {
        nav_status: 2,
        ..steps[0].clone()
    };
    set_inputs(&i, &failed);
    assert_eq!(i.step(0.0, dt), 3);
    assert!(i.last().contains("filter failed"), "{}", i.last());
    // Nothing changed: the same step with good inputs gives the core's bank.
    assert_eq!(i.int(Key::GuidanceCycles), 0);
    set_inputs(&i, &steps[0]);
    assert_eq!(i.step(0.0, dt), 0, "{}", i.last());
    assert_eq!(i.real(Key::GuidanceBank).to_bits(), steps[0].bank.to_bits());
    // Between cycles the estimate is not used, so it is not checked either.
    set_inputs(&i, &zero);
    assert_eq!(i.step(dt, dt), 0, "{}", i.last());
}

#[test]
fn the_bank_does_not_depend_on_the_communication_grid() {
    let (steps, dt) = core_run(28);
    // Inputs held at one mid-flight estimate, so every grid gives its cycles the same inputs.
    let s = &steps[steps.len() / 2];
    let end = 3.0;
    let run = |h: f64| {
        let i = guidance(&format!("grid{}", (h * 1000.0) as u32));
        assert_eq!(i.init(), [0, 0, 0]);
        set_inputs(&i, s);
        let n = (end / h).round() as usize;
        for k in 0..n {
            assert_eq!(i.step(k as f64 * h, h), 0, "{}", i.last());
        }
        let warned = i
            .messages()
            .iter()
            .any(|m| m.0 == 1 && m.2.contains("guidance cycles"));
        (
            i.real(Key::GuidanceBank).to_bits(),
            i.int(Key::GuidanceCycles),
            warned,
        )
    };
    let (bank, cycles, warned) = run(dt);
    assert_eq!(cycles, 3);
    assert!(!warned);
    // A step shorter than the truth step and not a divisor of the guidance period.
    assert_eq!(run(0.02), (bank, 3, false));
    // One step over three guidance periods: the same bank, and a warning that every cycle
    // saw the same inputs.
    assert_eq!(run(end), (bank, 3, true));
}

#[test]
fn an_fmu_state_taken_mid_flight_replays_the_rest_bit_for_bit() {
    use entrynav_fmu::ffi::{fmi2FreeFMUstate, fmi2GetFMUstate, fmi2SetFMUstate};
    let (steps, dt) = core_run(28);
    let i = guidance("state");
    assert_eq!(i.init(), [0, 0, 0]);
    let half = steps.len() / 2;
    let run = |from: usize, to: usize| -> Vec<u64> {
        (from..to)
            .map(|k| {
                set_inputs(&i, &steps[k]);
                assert_eq!(i.step(steps[k].t, dt), 0, "{}", i.last());
                i.real(Key::GuidanceBank).to_bits()
            })
            .collect()
    };
    run(0, half);
    let mut st = std::ptr::null_mut();
    // SAFETY: our instance and a pointer to receive the state.
    assert_eq!(unsafe { fmi2GetFMUstate(i.c, &mut st) }, 0, "{}", i.last());
    let first = run(half, half + 400);
    // SAFETY: the state this instance gave.
    assert_eq!(unsafe { fmi2SetFMUstate(i.c, st) }, 0, "{}", i.last());
    assert_eq!(run(half, half + 400), first);
    // The replayed bank is the core loop's.
    assert_eq!(first[399], steps[half + 399].bank.to_bits());
    // SAFETY: the state this instance gave, freed once.
    assert_eq!(unsafe { fmi2FreeFMUstate(i.c, &mut st) }, 0);
}

mod random {
    use super::*;
    use entrynav_fmu::vars::{Causality, Type, variables};
    use proptest::prelude::*;

    /// A value in the flight envelope, at its edges, beyond them, or not finite.
    fn wild(nominal: f64) -> impl Strategy<Value = f64> {
        prop_oneof![
            4 => (-0.5f64..0.5).prop_map(move |e| nominal * (1.0 + e)),
            1 => Just(0.0),
            1 => Just(-nominal),
            1 => Just(nominal * 1e6),
            1 => Just(f64::NAN),
            1 => Just(f64::INFINITY),
        ]
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 24, ..ProptestConfig::default() })]

        /// Any inputs, any step sizes: no panic reaches the logger, every status is OK, a warning
        /// or a logged fmi2Error, and no Real output is ever NaN or infinite.
        #[test]
        fn any_inputs_are_answered_and_no_output_is_ever_non_finite(
            steps in proptest::collection::vec(
                (
                    proptest::collection::vec(wild(1.0), 6),
                    wild(1.0),
                    -1i32..4,
                    proptest::collection::vec(wild(-5.0), 3),
                    any::<bool>(),
                    prop_oneof![Just(0.05), Just(0.02), Just(1.0), Just(7.3)],
                ),
                1..12,
            )
        ) {
            let nominal = [3_522_200.0, 2.21, -0.068, 6083.3, -0.27, 1.627];
            let i = guidance("random");
            prop_assert_eq!(i.init(), [0, 0, 0]);
            let outs: Vec<Key> = variables(Model::Guidance)
                .into_iter()
                .filter(|v| v.causality == Causality::Output && v.ty == Type::Real)
                .map(|v| v.key)
                .collect();
            let mut t = 0.0;
            for (x, sigma, status, accel, valid, h) in steps {
                for k in 0..6 {
                    let st = i.set_real(Key::EstX(k), x[k] * nominal[k]);
                    prop_assert!(st == 0 || (st == 3 && !(x[k] * nominal[k]).is_finite()));
                    let st = i.set_real(Key::EstSigma(k), sigma);
                    prop_assert!(st == 0 || st == 3);
                }
                let st = i.set_int(Key::NavStatusCode, status);
                prop_assert_eq!(st == 0, (0..=2).contains(&status));
                for k in 0..3u8 {
                    prop_assert!([0, 3].contains(&i.set_real(Key::Meas(Slot::Accel(k)), accel[k as usize])));
                    prop_assert_eq!(i.set_bool(Key::MeasValid(Slot::Accel(k)), valid), 0);
                }
                let st = i.step(t, h);
                prop_assert!([0, 1, 3].contains(&st), "status {}", st);
                if st == 3 {
                    prop_assert!(!i.last().is_empty());
                    if i.last().contains("refused") {
                        continue;
                    }
                    break; // a failure inside the law: the error state
                }
                t += h;
                for key in &outs {
                    let v = i.real(*key);
                    prop_assert!(v.is_finite(), "{:?} = {}", key, v);
                }
            }
            prop_assert!(!i.messages().iter().any(|m| m.2.contains("panic")), "{:?}", i.messages());
        }
    }
}
