//! Every exported fmi2 function obeys its entry of the allowed-state table: called in each phase
//! of an instance with harmless arguments, it answers "Illegal call sequence" exactly where
//! [`Fmi2::allowed`] says it may not be called (the table itself is checked against the FMI 2.0
//! standard in `instance::allowed`).

mod common;

use common::Inst;
use mars_entry_nav::ffi::*;
use mars_entry_nav::instance::Fmi2;
use mars_entry_nav::state::Phase;
use mars_entry_nav::vars::{Key, Model};
use std::ffi::c_void;
use std::ptr::{null, null_mut};

/// A fresh instance of the combined model brought into `phase`.
fn instance_in(phase: Phase) -> Inst {
    let i = Inst::new(Model::Combined);
    // SAFETY: our instance.
    unsafe {
        match phase {
            Phase::Instantiated => {}
            Phase::InitializationMode => {
                assert_eq!(fmi2SetupExperiment(i.c, 0, 0.0, 0.0, 0, 0.0), 0);
                assert_eq!(fmi2EnterInitializationMode(i.c), 0);
            }
            Phase::StepComplete => assert_eq!(i.init(), [0, 0, 0]),
            Phase::Terminated => {
                assert_eq!(i.init(), [0, 0, 0]);
                assert_eq!(fmi2Terminate(i.c), 0);
            }
            Phase::Error => {
                // DCIFAIF fuses one local filter per beacon; msl-airdata has none.
                assert_eq!(i.set_string(Key::Scenario, "msl-airdata"), 0);
                assert_eq!(i.set_string(Key::Filter, "dcifaif"), 0);
                assert_eq!(i.init(), [0, 0, 3]);
            }
        }
    }
    i
}

/// Call `f` on `c` with arguments that are harmless where the call is allowed (empty value
/// lists, null FMU states, the status kind each query answers); `None` for the functions that
/// take no instance.
fn call(f: Fmi2, c: *mut c_void) -> Option<i32> {
    let (mut r, mut i, mut s) = (0.0f64, 0i32, null_mut::<c_void>());
    let mut text = null();
    let mut n = 0usize;
    // SAFETY: a live instance; every pointer is valid or null with a zero length.
    let status = unsafe {
        match f {
            Fmi2::GetTypesPlatform | Fmi2::GetVersion | Fmi2::Instantiate | Fmi2::FreeInstance => {
                return None;
            }
            Fmi2::SetDebugLogging => fmi2SetDebugLogging(c, 0, 0, null()),
            Fmi2::SetupExperiment => fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0),
            Fmi2::EnterInitializationMode => fmi2EnterInitializationMode(c),
            Fmi2::ExitInitializationMode => fmi2ExitInitializationMode(c),
            Fmi2::Terminate => fmi2Terminate(c),
            Fmi2::Reset => fmi2Reset(c),
            Fmi2::GetReal => fmi2GetReal(c, null(), 0, null_mut()),
            Fmi2::GetInteger => fmi2GetInteger(c, null(), 0, null_mut()),
            Fmi2::GetBoolean => fmi2GetBoolean(c, null(), 0, null_mut()),
            Fmi2::GetString => fmi2GetString(c, null(), 0, null_mut()),
            Fmi2::SetReal => fmi2SetReal(c, null(), 0, null()),
            Fmi2::SetInteger => fmi2SetInteger(c, null(), 0, null()),
            Fmi2::SetBoolean => fmi2SetBoolean(c, null(), 0, null()),
            Fmi2::SetString => fmi2SetString(c, null(), 0, null()),
            Fmi2::GetFMUstate => fmi2GetFMUstate(c, &mut s),
            Fmi2::SetFMUstate => fmi2SetFMUstate(c, null_mut()),
            Fmi2::FreeFMUstate => fmi2FreeFMUstate(c, &mut s),
            Fmi2::SerializedFMUstateSize => fmi2SerializedFMUstateSize(c, null_mut(), &mut n),
            Fmi2::SerializeFMUstate => fmi2SerializeFMUstate(c, null_mut(), null_mut(), 0),
            Fmi2::DeSerializeFMUstate => fmi2DeSerializeFMUstate(c, null(), 0, &mut s),
            Fmi2::GetDirectionalDerivative => {
                fmi2GetDirectionalDerivative(c, null(), 0, null(), 0, null(), null_mut())
            }
            Fmi2::SetRealInputDerivatives => {
                fmi2SetRealInputDerivatives(c, null(), 0, null(), null())
            }
            Fmi2::GetRealOutputDerivatives => {
                fmi2GetRealOutputDerivatives(c, null(), 0, null(), null_mut())
            }
            Fmi2::DoStep => fmi2DoStep(c, 0.0, 1.0, 0),
            Fmi2::CancelStep => fmi2CancelStep(c),
            Fmi2::GetStatus => fmi2GetStatus(c, 0, &mut i),
            Fmi2::GetRealStatus => fmi2GetRealStatus(c, 2, &mut r),
            Fmi2::GetIntegerStatus => fmi2GetIntegerStatus(c, 0, &mut i),
            Fmi2::GetBooleanStatus => fmi2GetBooleanStatus(c, 3, &mut i),
            Fmi2::GetStringStatus => fmi2GetStringStatus(c, 1, &mut text),
        }
    };
    Some(status)
}

#[test]
fn every_function_is_refused_exactly_in_the_phases_its_entry_excludes() {
    let mut checked = 0;
    for phase in Phase::ALL {
        for &f in Fmi2::ALL {
            let i = instance_in(phase);
            i.log.lock().unwrap().clear();
            let Some(status) = call(f, i.c) else {
                continue;
            };
            let messages = i.messages();
            let illegal = messages
                .iter()
                .any(|m| m.2.starts_with(&format!("{f}: Illegal call sequence")));
            let allowed = f.allowed().contains(phase);
            assert_eq!(illegal, !allowed, "{f} in {phase:?}: {messages:?}");
            if !allowed {
                assert_eq!(status, 3, "{f} in {phase:?}");
            }
            checked += 1;
        }
    }
    assert_eq!(checked, 30 * Phase::ALL.len());
}
