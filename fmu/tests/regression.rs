//! The fuzzer's crash, for every filter through the C API: MarsEntryNavFilter, SetupExperiment
//! without a stop time, initialisation, DoStep(0, T) (fine: no epoch), then an epoch at T and
//! DoStep(T, 1). The filter would have to predict over T seconds; before the work bounds it
//! allocated T / filter_step entries and aborted the process (T = 1e9) or panicked (T = 1e18).
//! Now the FMU refuses the step with fmi2Error and a logged reason, changes nothing, and the run
//! goes on.

mod common;

use common::Inst;
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::{BUILTIN_NAMES, Scenario, ScenarioConfig};
use entrynav_fmu::vars::{Key, Model};

/// The first built-in scenario `kind` fits.
fn scenario_for(kind: FilterKind) -> &'static str {
    BUILTIN_NAMES
        .into_iter()
        .find(|n| {
            let s = Scenario::build(
                ScenarioConfig::builtin(n).unwrap(),
                &entrynav::files::no_files,
            )
            .unwrap();
            kind.misfit(&s.onboard).is_none()
        })
        .unwrap_or_else(|| panic!("no built-in scenario fits {}", kind.name()))
}

#[test]
fn a_prediction_too_long_for_one_step_is_refused_for_every_filter() {
    for kind in FilterKind::ALL {
        let scenario = scenario_for(kind);
        for t_far in [1e9, 1e18] {
            let i = Inst::new(Model::Filter);
            assert_eq!(i.set_string(Key::Scenario, scenario), 0);
            assert_eq!(i.set_string(Key::Filter, kind.name()), 0);
            assert_eq!(i.init(), [0, 0, 0], "{}: {}", kind.name(), i.last());
            assert_eq!(i.step(0.0, t_far), 0, "{}", i.last());
            assert_eq!(i.set_bool(Key::MeasEpoch, true), 0);
            assert_eq!(i.set_real(Key::MeasTime, t_far), 0);
            let n = i.messages().len();
            assert_eq!(i.step(t_far, 1.0), 3, "{} at {t_far}", kind.name());
            let msgs = i.messages();
            let reason = &msgs[n..];
            assert!(
                reason.len() == 1
                    && reason[0].0 == 3
                    && reason[0].2.contains("refused, the instance is unchanged")
                    && reason[0].2.contains("sub-steps"),
                "{} at {t_far}: {reason:?}",
                kind.name()
            );
            // Unchanged: no epoch processed, still at T, and the run goes on.
            assert_eq!(i.int(Key::NavStatus), 0, "{}", kind.name());
            assert_eq!(i.real(Key::NavTime), 0.0);
            assert_eq!(i.set_bool(Key::MeasEpoch, false), 0);
            assert_eq!(i.step(t_far, 1.0), 0, "{}: {}", kind.name(), i.last());
            assert!(msgs.iter().all(|m| !m.2.contains("panic")), "{msgs:?}");
        }
    }
}

#[test]
fn an_epoch_after_the_scenario_duration_is_refused_and_a_reachable_one_is_processed() {
    let i = Inst::new(Model::Filter);
    assert_eq!(i.set_string(Key::Filter, "ekf"), 0);
    assert_eq!(i.init(), [0, 0, 0], "{}", i.last());
    // four-beacon-fusion lasts 300 s at a 1 s filter step: 301 s is not a truth epoch.
    assert_eq!(i.set_bool(Key::MeasEpoch, true), 0);
    assert_eq!(i.set_real(Key::MeasTime, 301.0), 0);
    assert_eq!(i.step(0.0, 400.0), 3);
    assert!(
        i.last().contains("after the scenario's duration"),
        "{}",
        i.last()
    );
    // An epoch 250 s ahead is 250 sub-steps: processed in one step.
    assert_eq!(i.set_real(Key::MeasTime, 250.0), 0);
    assert!(i.step(0.0, 400.0) <= 1, "{}", i.last());
    assert_eq!(i.real(Key::NavTime), 250.0);
    assert_eq!(i.int(Key::NavStatus), 1);
}

#[test]
fn huge_and_tiny_steps_of_the_combined_model_run_and_stop_at_the_duration() {
    let i = Inst::new(Model::Combined);
    assert_eq!(i.set_string(Key::Filter, "ekf"), 0);
    assert_eq!(i.init(), [0, 0, 0]);
    for h in [5e-324, 1e-300, 1e-9] {
        assert!(i.step(0.0, h) <= 1, "{h}: {}", i.last());
    }
    let t = 1e-9;
    assert!(i.step(t, 1e300) <= 1, "{}", i.last());
    assert_eq!(i.int(Key::TruthStop), 1, "the truth stops at the duration");
    assert_eq!(i.real(Key::NavTime), 300.0);
    // f64::MAX after 1e300 overflows to inf: refused, nothing changes.
    assert_eq!(i.step(t + 1e300, f64::MAX), 3);
    assert!(i.step(t + 1e300, 1.0) <= 1, "{}", i.last());
}
