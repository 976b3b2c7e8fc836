//! Every exported fmi2 function obeys its entry of the allowed-state table: called in each phase
//! of an instance with harmless arguments, it answers "Illegal call sequence" exactly where
//! [`Operation::allowed`] says it may not be called (the table itself is checked against the FMI 2.0
//! standard in `instance::allowed`).

mod common;

use common::Inst;
use entrynav_fmu::ffi::*;
use entrynav_fmu::instance::Operation;
use entrynav_fmu::state::Phase;
use entrynav_fmu::vars::{Key, Model};
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
fn call(f: Operation, c: *mut c_void) -> Option<i32> {
    let (mut r, mut i, mut s) = (0.0f64, 0i32, null_mut::<c_void>());
    let mut text = null();
    let mut n = 0usize;
    // SAFETY: a live instance; every pointer is valid or null with a zero length.
    let status = unsafe {
        match f {
            Operation::GetTypesPlatform
            | Operation::GetVersion
            | Operation::Instantiate
            | Operation::FreeInstance => {
                return None;
            }
            Operation::SetDebugLogging => fmi2SetDebugLogging(c, 0, 0, null()),
            Operation::SetupExperiment => fmi2SetupExperiment(c, 0, 0.0, 0.0, 0, 0.0),
            Operation::EnterInitializationMode => fmi2EnterInitializationMode(c),
            Operation::ExitInitializationMode => fmi2ExitInitializationMode(c),
            Operation::Terminate => fmi2Terminate(c),
            Operation::Reset => fmi2Reset(c),
            Operation::GetReal => fmi2GetReal(c, null(), 0, null_mut()),
            Operation::GetInteger => fmi2GetInteger(c, null(), 0, null_mut()),
            Operation::GetBoolean => fmi2GetBoolean(c, null(), 0, null_mut()),
            Operation::GetString => fmi2GetString(c, null(), 0, null_mut()),
            Operation::SetReal => fmi2SetReal(c, null(), 0, null()),
            Operation::SetInteger => fmi2SetInteger(c, null(), 0, null()),
            Operation::SetBoolean => fmi2SetBoolean(c, null(), 0, null()),
            Operation::SetString => fmi2SetString(c, null(), 0, null()),
            Operation::GetFMUstate => fmi2GetFMUstate(c, &mut s),
            Operation::SetFMUstate => fmi2SetFMUstate(c, null_mut()),
            Operation::FreeFMUstate => fmi2FreeFMUstate(c, &mut s),
            Operation::SerializedFMUstateSize => fmi2SerializedFMUstateSize(c, null_mut(), &mut n),
            Operation::SerializeFMUstate => fmi2SerializeFMUstate(c, null_mut(), null_mut(), 0),
            Operation::DeSerializeFMUstate => fmi2DeSerializeFMUstate(c, null(), 0, &mut s),
            Operation::GetDirectionalDerivative => {
                fmi2GetDirectionalDerivative(c, null(), 0, null(), 0, null(), null_mut())
            }
            Operation::SetRealInputDerivatives => {
                fmi2SetRealInputDerivatives(c, null(), 0, null(), null())
            }
            Operation::GetRealOutputDerivatives => {
                fmi2GetRealOutputDerivatives(c, null(), 0, null(), null_mut())
            }
            Operation::DoStep => fmi2DoStep(c, 0.0, 1.0, 0),
            Operation::CancelStep => fmi2CancelStep(c),
            Operation::GetStatus => fmi2GetStatus(c, 0, &mut i),
            Operation::GetRealStatus => fmi2GetRealStatus(c, 2, &mut r),
            Operation::GetIntegerStatus => fmi2GetIntegerStatus(c, 0, &mut i),
            Operation::GetBooleanStatus => fmi2GetBooleanStatus(c, 3, &mut i),
            Operation::GetStringStatus => fmi2GetStringStatus(c, 1, &mut text),
        }
    };
    Some(status)
}

#[test]
fn every_function_is_refused_exactly_in_the_phases_its_entry_excludes() {
    let mut checked = 0;
    for phase in Phase::ALL {
        for &f in Operation::ALL {
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
