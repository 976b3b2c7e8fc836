//! `MarsEntryNavGuided` through the C API: truth, filter and guidance in one FMU deliver the
//! vehicle exactly where the in-process guided loop (`entrynav guidance deliver`) does, on any
//! communication grid; after the end the outputs hold; bad parameters are refused.

mod common;

use common::Inst;
use entrynav::estimation::nav::FilterKind;
use entrynav::sim::guided::{Delivery, GuidedStep, fly_with_filter_recorded};
use entrynav_fmu::vars::{GUIDED_SCENARIO_FILE, Key, Model, guided_scenario, guided_scenario_toml};
use std::path::PathBuf;
use std::sync::Arc;

/// A resources folder holding the guided scenario, as `entrynav fmu pack` ships it.
fn resources(tag: &str) -> PathBuf {
    let dir =
        std::env::temp_dir().join(format!("entrynav-guided-fmu-{tag}-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    std::fs::write(dir.join(GUIDED_SCENARIO_FILE), guided_scenario_toml()).unwrap();
    dir
}

fn guided(tag: &str) -> Inst {
    let dir = resources(tag);
    Inst::with(Model::Guided, Some(dir.to_str().unwrap()), true)
}

/// Run `run` of seed `seed` in process with the EKF in the loop, every truth step recorded.
fn core_run(seed: u64, run: usize) -> (Delivery, Vec<GuidedStep>, f64) {
    let scenario = Arc::new(guided_scenario().unwrap());
    let dt = scenario.config.timing.truth_step_s;
    let mut steps = Vec::new();
    let d = fly_with_filter_recorded(&scenario, FilterKind::Ekf, seed, run, |s| {
        steps.push(s.clone())
    })
    .expect("this run delivers in process");
    (d, steps, dt)
}

/// Fly the FMU (EKF, dispersed run `run` of `seed`) with communication step `h` until it reports
/// the end; the flown bank at every communication point is checked against the in-process steps.
fn fly_fmu(tag: &str, seed: i32, run: i32, h: f64, steps: &[GuidedStep], dt: f64) -> (Inst, f64) {
    let i = guided(tag);
    assert_eq!(i.set_string(Key::Filter, "ekf"), 0);
    assert_eq!(i.set_int(Key::Seed, seed), 0);
    assert_eq!(i.set_bool(Key::Dispersed, true), 0);
    assert_eq!(i.set_int(Key::Run, run), 0);
    assert_eq!(i.init(), [0, 0, 0], "{:?}", i.messages());
    let mut t = 0.0;
    let mut k = 0usize;
    while i.int(Key::GuidedStatus) == 0 {
        assert!(t < 2000.0, "no end by t = {t}");
        assert_eq!(i.step(t, h), 0, "{:?}", i.messages());
        k += 1;
        t = k as f64 * h;
        // The grid steps that ended at or before t were flown; the last one's bank is output.
        let flown = ((t / dt + 1e-7).floor() as usize).min(steps.len());
        if i.int(Key::GuidedStatus) == 0 {
            assert_eq!(
                i.real(Key::TruthBankFlown).to_bits(),
                steps[flown - 1].bank.to_bits(),
                "bank flown at t = {t} (h = {h})"
            );
        }
    }
    (i, t)
}

#[test]
fn delivers_where_guidance_deliver_does_bit_for_bit_on_any_grid() {
    let (d, steps, dt) = core_run(5, 2);
    for (tag, h) in [("dt", dt), ("period", 1.0), ("odd", 2.35)] {
        let (i, mut t) = fly_fmu(tag, 5, 2, h, &steps, dt);
        assert_eq!(i.int(Key::GuidedStatus), 1, "{:?}", i.messages());
        assert!(i.boolean(Key::Deployed));
        for (key, want) in [
            (Key::DeployTime, d.t_deploy_s),
            (Key::DeployAltitude, d.altitude_m),
            (Key::MissDistance, d.miss_m),
            (Key::MissDownrange, d.downrange_m),
            (Key::MissCrossrange, d.crossrange_m),
        ] {
            assert_eq!(
                i.real(key).to_bits(),
                want.to_bits(),
                "{key:?} with h = {h}"
            );
        }
        // Guidance ran and the log says where it deployed.
        assert!(i.int(Key::GuidanceCycles) > 100);
        assert!(
            i.messages().iter().any(|m| m.2.contains("deployed at t =")),
            "{:?}",
            i.messages()
        );
        // After deployment the outputs hold and a step only advances time.
        let miss = i.real(Key::MissDistance);
        let alt = i.real(Key::TruthAltitude);
        let cycles = i.int(Key::GuidanceCycles);
        for _ in 0..5 {
            assert_eq!(i.step(t, h), 0, "{:?}", i.messages());
            t += h;
            assert_eq!(i.real(Key::MissDistance), miss);
            assert_eq!(i.real(Key::TruthAltitude), alt);
            assert_eq!(i.int(Key::GuidanceCycles), cycles);
            assert_eq!(i.int(Key::GuidedStatus), 1);
        }
    }
}

#[test]
fn the_nominal_entry_deploys_near_the_target_and_the_bank_rate_limit_holds() {
    let scenario = guided_scenario().unwrap();
    let rate_max = scenario
        .config
        .guidance
        .as_ref()
        .unwrap()
        .bank_rate_limit_deg_s;
    let dt = scenario.config.timing.truth_step_s;
    let i = guided("nominal");
    assert_eq!(i.init(), [0, 0, 0], "{:?}", i.messages());
    let mut t = 0.0;
    let mut prev = i.real(Key::TruthBankFlown);
    let mut k = 0;
    while i.int(Key::GuidedStatus) == 0 && t < 2000.0 {
        assert_eq!(i.step(t, dt), 0, "{:?}", i.messages());
        k += 1;
        let bank = i.real(Key::TruthBankFlown);
        if k > 1 {
            assert!(
                (bank - prev).abs() <= rate_max.to_radians() * dt * (1.0 + 1e-9),
                "rate limit broken at t = {t}"
            );
        }
        prev = bank;
        t = k as f64 * dt;
    }
    assert_eq!(i.int(Key::GuidedStatus), 1, "{:?}", i.messages());
    // The EKF in the loop on the undispersed entry (Apollo guidance): within a few km.
    let miss = i.real(Key::MissDistance);
    println!(
        "nominal entry, EKF: deployed at t = {:.2} s at {:.0} m, miss {miss:.0} m",
        i.real(Key::DeployTime),
        i.real(Key::DeployAltitude)
    );
    assert!(miss > 0.0 && miss < 5000.0, "miss {miss} m");
}

#[test]
fn refuses_a_scenario_without_guidance_and_a_run_out_of_range() {
    let i = guided("noguid");
    assert_eq!(i.set_string(Key::Scenario, "four-beacon-fusion"), 0);
    let [_, _, exit] = i.init();
    assert_ne!(exit, 0);
    assert!(i.last().contains("[guidance]"), "{}", i.last());
    let i = guided("run");
    assert_ne!(i.set_int(Key::Run, -1), 0);
    assert!(
        i.last().contains("run must be in 0..=999999999, got -1"),
        "{}",
        i.last()
    );
    assert_ne!(i.set_int(Key::Run, i32::MAX), 0);
}

#[test]
fn an_fmu_state_taken_mid_flight_delivers_the_same_vehicle_again() {
    use entrynav_fmu::ffi::{fmi2FreeFMUstate, fmi2GetFMUstate, fmi2SetFMUstate};
    let (d, _, _) = core_run(5, 2);
    let i = guided("state");
    assert_eq!(i.set_int(Key::Seed, 5), 0);
    assert_eq!(i.set_bool(Key::Dispersed, true), 0);
    assert_eq!(i.set_int(Key::Run, 2), 0);
    assert_eq!(i.init(), [0, 0, 0], "{:?}", i.messages());
    // Fly 120 s in 1 s steps, keep the state, fly to the end, go back and fly to the end again.
    for k in 0..120 {
        assert_eq!(i.step(k as f64, 1.0), 0, "{}", i.last());
    }
    let mut st = std::ptr::null_mut();
    // SAFETY: our instance and a pointer to receive the state.
    assert_eq!(unsafe { fmi2GetFMUstate(i.c, &mut st) }, 0, "{}", i.last());
    let finish = || {
        let mut k = 120;
        while i.int(Key::GuidedStatus) == 0 {
            assert!(k < 400, "no deployment by t = {k}");
            assert_eq!(i.step(k as f64, 1.0), 0, "{}", i.last());
            k += 1;
        }
        (
            i.real(Key::DeployTime).to_bits(),
            i.real(Key::MissDistance).to_bits(),
        )
    };
    let first = finish();
    assert_eq!(first, (d.t_deploy_s.to_bits(), d.miss_m.to_bits()));
    // SAFETY: the state this instance gave.
    assert_eq!(unsafe { fmi2SetFMUstate(i.c, st) }, 0, "{}", i.last());
    assert_eq!(i.int(Key::GuidedStatus), 0);
    assert_eq!(finish(), first);
    // SAFETY: the state this instance gave, freed once.
    assert_eq!(unsafe { fmi2FreeFMUstate(i.c, &mut st) }, 0);
}
