//! No output of any FMU is NaN or infinite at any step from initialisation on (issue "FMI 3.0 and
//! system-level tools"): OMSimulator rejects a NaN output and drops the step's whole result row.
//! Every Real output of the three generic models is read through the C API in initialisation mode
//! and after every step: the combined FMU with every filter on a built-in it fits, the truth FMU on
//! every built-in with a 2 s communication step (longer than every sensor period: the step must
//! succeed, fmi2OK), the filter FMU alone (no measurement ever: NIS and NEES undefined throughout)
//! and the split pair (filter fed from the truth one step late).

mod common;

use common::Inst;
use entrynav::estimation::nav::FilterKind;
use entrynav::scenario::{BUILTIN_NAMES, Scenario, ScenarioConfig};
use entrynav_fmu::ffi::*;
use entrynav_fmu::vars::{Causality, Key, Model, Type, Var, variables};
use std::ffi::c_int;

fn scenario(name: &str) -> Scenario {
    Scenario::build(
        ScenarioConfig::builtin(name).unwrap(),
        &entrynav::files::no_files,
    )
    .unwrap()
}

/// Every Real output of `inst` is finite; `when` names the point for the message.
fn assert_finite(inst: &Inst, when: &str) {
    let outs: Vec<Var> = variables(inst.model)
        .into_iter()
        .filter(|v| v.causality == Causality::Output && v.ty == Type::Real)
        .collect();
    let vrs: Vec<u32> = outs.iter().map(|v| v.vr).collect();
    let mut vals = vec![0.0; vrs.len()];
    // SAFETY: our instance; vrs.len() references and as many values.
    let st = unsafe { fmi2GetReal(inst.c, vrs.as_ptr(), vrs.len(), vals.as_mut_ptr()) };
    assert_eq!(st, 0, "{when}: fmi2GetReal {}", inst.last());
    for (v, x) in outs.iter().zip(&vals) {
        assert!(x.is_finite(), "{when}: {} = {x}", v.name);
    }
}

/// SetupExperiment and EnterInitializationMode, the outputs checked there, then Exit.
fn init_checked(inst: &Inst, what: &str) {
    // SAFETY: our instance.
    unsafe {
        assert_eq!(fmi2SetupExperiment(inst.c, 0, 0.0, 0.0, 0, 0.0), 0);
        assert_eq!(fmi2EnterInitializationMode(inst.c), 0, "{}", inst.last());
    }
    assert_finite(inst, &format!("{what} in initialisation mode"));
    // SAFETY: our instance.
    assert_eq!(
        unsafe { fmi2ExitInitializationMode(inst.c) },
        0,
        "{what}: {}",
        inst.last()
    );
    assert_finite(inst, &format!("{what} at t = 0"));
}

/// The fastest sensor period and the duration of built-in `name`.
fn timing(name: &str) -> (f64, f64) {
    let sc = scenario(name);
    let h = sc
        .channels
        .iter()
        .map(|c| c.period_s)
        .fold(f64::INFINITY, f64::min);
    (h, sc.config.timing.duration_s)
}

#[test]
fn the_combined_fmu_never_outputs_nan_with_any_filter() {
    for kind in FilterKind::ALL {
        let name = BUILTIN_NAMES
            .into_iter()
            .find(|n| kind.misfit(&scenario(n).onboard).is_none())
            .unwrap();
        let what = format!("MarsEntryNav {} on {name}", kind.name());
        let i = Inst::new(Model::Combined);
        assert_eq!(i.set_string(Key::Scenario, name), 0);
        assert_eq!(i.set_string(Key::Filter, kind.name()), 0);
        init_checked(&i, &what);
        let (h, end) = timing(name);
        let n = (end / h).round() as usize;
        for k in 0..n {
            let t = k as f64 * h;
            assert!(i.step(t, h) <= 1, "{what} at {t}: {}", i.last());
            assert_finite(&i, &format!("{what} after the step at {t}"));
        }
    }
}

#[test]
fn the_truth_fmu_steps_longer_than_a_sensor_period_with_ok_and_no_nan() {
    for name in BUILTIN_NAMES {
        let what = format!("MarsEntryTruth on {name}");
        let i = Inst::new(Model::Truth);
        assert_eq!(i.set_string(Key::Scenario, name), 0);
        init_checked(&i, &what);
        let (h, end) = timing(name);
        assert!(h < 2.0, "{name}: no sensor faster than the 2 s step");
        let mut t = 0.0;
        while t < end {
            assert_eq!(i.step(t, 2.0), 0, "{what} at {t}: {}", i.last());
            assert_finite(&i, &format!("{what} after the step at {t}"));
            t += 2.0;
        }
        // Reported once at warning level, the step still fmi2OK.
        let msgs = i.messages();
        let spans: Vec<_> = msgs.iter().filter(|m| m.2.contains("spans")).collect();
        assert_eq!(spans.len(), 1, "{what}: {msgs:?}");
        assert_eq!(spans[0].0, 1, "{what}: {msgs:?}");
    }
}

#[test]
fn the_filter_fmu_alone_and_fed_from_the_truth_never_outputs_nan() {
    let name = "four-beacon-fusion";
    let (h, end) = timing(name);
    let n = (end / h).round() as usize;
    // Alone: no measurement ever, so the NIS and NEES are undefined at every step.
    let alone = Inst::new(Model::Filter);
    assert_eq!(alone.set_string(Key::Filter, "dcifaif"), 0);
    init_checked(&alone, "MarsEntryNavFilter alone");
    for k in 0..n {
        let t = k as f64 * h;
        assert!(alone.step(t, h) <= 1, "{}", alone.last());
        assert_finite(&alone, &format!("the filter alone after the step at {t}"));
    }
    assert_eq!(alone.int(Key::NMeas), 0);
    assert_eq!(alone.real(Key::Nis), 0.0);
    // The split pair: the truth's measurement outputs into the filter's inputs after each step.
    let truth = Inst::new(Model::Truth);
    let filter = Inst::new(Model::Filter);
    assert_eq!(filter.set_string(Key::Filter, "dcifaif"), 0);
    init_checked(&truth, "MarsEntryTruth");
    init_checked(&filter, "MarsEntryNavFilter");
    let truth_vars = variables(Model::Truth);
    let links: Vec<(Var, Var)> = variables(Model::Filter)
        .into_iter()
        .filter(|v| v.causality == Causality::Input && v.key != Key::Bank)
        .filter_map(|fv| {
            let tv = truth_vars
                .iter()
                .find(|tv| tv.name == fv.name && tv.causality == Causality::Output)?;
            Some((tv.clone(), fv))
        })
        .collect();
    assert!(links.len() > 5, "{links:?}");
    let mut saw_nis = false;
    for k in 0..n {
        let t = k as f64 * h;
        assert_eq!(truth.step(t, h), 0, "{}", truth.last());
        for (tv, fv) in &links {
            // SAFETY: our instances; one reference and one value each.
            unsafe {
                match tv.ty {
                    Type::Real => {
                        let mut x = 0.0;
                        assert_eq!(fmi2GetReal(truth.c, &tv.vr, 1, &mut x), 0);
                        assert_eq!(fmi2SetReal(filter.c, &fv.vr, 1, &x), 0);
                    }
                    Type::Boolean => {
                        let mut b: c_int = 0;
                        assert_eq!(fmi2GetBoolean(truth.c, &tv.vr, 1, &mut b), 0);
                        assert_eq!(fmi2SetBoolean(filter.c, &fv.vr, 1, &b), 0);
                    }
                    _ => {}
                }
            }
        }
        assert!(filter.step(t, h) <= 1, "{}", filter.last());
        assert_finite(&filter, &format!("the split filter after the step at {t}"));
        saw_nis |= filter.real(Key::Nis) > 0.0;
    }
    assert!(saw_nis, "the split filter never updated");
}
