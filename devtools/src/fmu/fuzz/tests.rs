//! The fuzzer against the FMU code linked into the test (no packed FMU): both versions pass, and
//! planted misbehaviours are reported — a library function that answers wrongly, an FMI 3.0 step
//! that raises a flag, a model that expects the wrong answer.

use super::fmi2::Fmi2;
use super::fmi3::Fmi3;
use super::fuzzer::{Fuzzer, Version};
use super::run;
use entrynav_fmi_host::{Api, Api3, file_uri};
use entrynav_fmu::vars::{Model, ModelSpec};
use std::ffi::c_void;
use std::path::PathBuf;
use std::sync::Arc;

/// An empty resources folder (the generic models need none for the built-in scenarios).
fn resources() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("entrynav-dev-fuzz-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn fmi2(model: Model, api: Api) -> Fuzzer<Fmi2> {
    let spec = Arc::new(ModelSpec::generic(model));
    let v = Fmi2 {
        api: Arc::new(api),
        guid: spec.guid().to_string(),
        uri: file_uri(&resources()),
    };
    Fuzzer::new(v, spec, false, 5).unwrap()
}

fn fmi3(model: Model, api: Api3) -> Fuzzer<Fmi3> {
    let spec = Arc::new(ModelSpec::generic(model));
    let v = Fmi3::load(api, spec.guid(), &resources()).unwrap();
    Fuzzer::new(v, spec, false, 5).unwrap()
}

/// The error of a run that must fail, with the statuses it got through.
fn failure<V: Version>(mut f: Fuzzer<V>, calls: usize) -> String {
    match run(&mut f, calls, 40) {
        Ok(report) => panic!("the planted misbehaviour was not reported: {report}"),
        Err(e) => {
            let e = format!("{e:#}");
            println!("reported: {e}");
            e
        }
    }
}

#[test]
fn both_versions_pass_on_the_linked_fmu() {
    for model in [Model::Truth, Model::Filter] {
        let report = run(&mut fmi2(model, Api::linked()), 20_000, 40).unwrap();
        assert!(report.contains("no crash"), "{report}");
        let report = run(&mut fmi3(model, Api3::linked()), 20_000, 40).unwrap();
        assert!(report.contains("(FMI 3.0)"), "{report}");
    }
}

/// fmi2Terminate answering fmi2OK in every state, without terminating.
unsafe extern "C" fn terminate_always_ok(_: *mut c_void) -> i32 {
    0
}

#[test]
fn a_function_that_answers_ok_where_it_must_refuse_is_reported() {
    let mut api = Api::linked();
    api.fmi2Terminate = terminate_always_ok;
    let e = failure(fmi2(Model::Truth, api), 20_000);
    assert!(e.contains("Terminate"), "{e}");
}

/// fmi3DoStep that steps, then asks for event handling (this FMU has no event mode).
#[allow(clippy::too_many_arguments)]
unsafe extern "C" fn do_step_with_event(
    c: *mut c_void,
    t: f64,
    h: f64,
    no_prior: u8,
    event: *mut u8,
    terminate: *mut u8,
    early: *mut u8,
    last: *mut f64,
) -> i32 {
    // SAFETY: the master's arguments, passed on.
    let r =
        unsafe { entrynav_fmu::ffi::fmi3DoStep(c, t, h, no_prior, event, terminate, early, last) };
    if r == 0 && !event.is_null() {
        // SAFETY: the master's flag.
        unsafe { *event = 1 };
    }
    r
}

#[test]
fn an_fmi3_step_that_asks_for_event_handling_is_reported() {
    let mut api = Api3::linked();
    api.fmi3DoStep = do_step_with_event;
    let e = failure(fmi3(Model::Truth, api), 20_000);
    assert!(e.contains("eventHandlingNeeded"), "{e}");
}

#[test]
fn a_model_that_expects_the_wrong_answer_is_reported() {
    // The model believes no filter fits any scenario: initialisation must fail, the FMU succeeds.
    for (f, version) in [
        (failure_of(fmi2(Model::Filter, Api::linked())), "2.0"),
        (failure_of(fmi3(Model::Filter, Api3::linked())), "3.0"),
    ] {
        assert!(f.contains("ExitInitializationMode"), "FMI {version}: {f}");
        assert!(f.contains("expected Fails"), "FMI {version}: {f}");
    }
}

fn failure_of<V: Version>(mut f: Fuzzer<V>) -> String {
    for fits in f.sc.fits.values_mut() {
        fits.clear();
    }
    failure(f, 20_000)
}
