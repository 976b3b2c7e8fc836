//! The FMI 3.0 co-simulation interface: the 75 `fmi3*` functions, over the same safe instance,
//! registry, limits and panic guard as the FMI 2.0 functions.
//!
//! One library exports both interfaces; an instance belongs to the interface that instantiated
//! it (an `fmi3Instance` is a registry token like an `fmi2Component`). The FMI 3.0 state machine
//! of co-simulation without event mode has the same states as this FMU's FMI 2.0 machine
//! (*Instantiated*, *Initialization Mode*, *Step Mode* = FMI 2.0's *stepComplete*, *Terminated*,
//! the error state), and each FMI 3.0 function this FMU supports is allowed in exactly the states
//! of the FMI 2.0 operation it maps to ([`MAPPED`]; the test at the end compares the two tables),
//! so the instance's one allowed-state table serves both. The mapping:
//!
//! | FMI 3.0 | instance operation |
//! |---|---|
//! | fmi3InstantiateCoSimulation | fmi2Instantiate (resource *path*, not URI; no event mode, no intermediate update) |
//! | fmi3EnterInitializationMode | fmi2SetupExperiment, then fmi2EnterInitializationMode |
//! | fmi3GetFloat64 / Int32 / Int64 / Boolean / String | fmi2GetReal / Integer / Integer (Enumerations) / Boolean / String, plus `time`, the arrays and the structural parameter (UInt64) |
//! | fmi3DoStep | fmi2DoStep; never asks for event handling, never terminates, never returns early |
//! | fmi3Get/Set/Free/Serialize…FMUState, Terminate, Reset, FreeInstance | their fmi2 namesakes |
//!
//! Everything else (model exchange, scheduled execution, event and configuration mode, clocks,
//! derivatives, the variable types without variables: Float32, Int8–UInt32, Binary) returns
//! `fmi3Error` with a logged reason (or NULL for the other instantiation functions). Messages
//! reach the master's `fmi3LogMessageCallback` in FMI 3.0 terms ([`in_fmi3_terms`]).

mod lifecycle;
pub(super) mod terms;
mod unsupported;
mod values;

pub use lifecycle::*;
pub use terms::in_fmi3_terms;
pub use unsupported::*;
pub use values::*;

use crate::instance::Operation;

/// The FMI 3.0 functions this FMU supports and the instance operation each maps to.
pub const MAPPED: [(&str, Operation); 20] = [
    ("fmi3SetDebugLogging", Operation::SetDebugLogging),
    ("fmi3FreeInstance", Operation::FreeInstance),
    (
        "fmi3EnterInitializationMode",
        Operation::EnterInitializationMode,
    ),
    (
        "fmi3ExitInitializationMode",
        Operation::ExitInitializationMode,
    ),
    ("fmi3Terminate", Operation::Terminate),
    ("fmi3Reset", Operation::Reset),
    ("fmi3GetFloat64", Operation::GetReal),
    ("fmi3GetInt32", Operation::GetInteger),
    ("fmi3GetInt64", Operation::GetInteger),
    ("fmi3GetUInt64", Operation::GetInteger),
    ("fmi3GetBoolean", Operation::GetBoolean),
    ("fmi3GetString", Operation::GetString),
    ("fmi3SetFloat64", Operation::SetReal),
    ("fmi3SetInt32", Operation::SetInteger),
    ("fmi3SetInt64", Operation::SetInteger),
    ("fmi3SetUInt64", Operation::SetInteger),
    ("fmi3SetBoolean", Operation::SetBoolean),
    ("fmi3SetString", Operation::SetString),
    ("fmi3GetFMUState", Operation::GetFMUstate),
    ("fmi3DoStep", Operation::DoStep),
];

#[cfg(test)]
mod tests {
    use super::*;
    use crate::state::Phase::{self, *};

    /// The FMI 3.0 co-simulation state table (FMI 3.0.1 §4.2.3, without event mode) restricted
    /// to the states of this FMU, columns *Instantiated*, *Initialization Mode*, *Step Mode*,
    /// *Terminated*, error state; `x` allowed.
    const STANDARD3: [(&str, &str); 20] = [
        ("fmi3SetDebugLogging", "xxxxx"),
        ("fmi3FreeInstance", "xxxxx"),
        ("fmi3EnterInitializationMode", "x...."),
        ("fmi3ExitInitializationMode", ".x..."),
        ("fmi3Terminate", "..x.."),
        ("fmi3Reset", "xxxxx"),
        ("fmi3GetFloat64", ".xxxx"),
        ("fmi3GetInt32", ".xxxx"),
        ("fmi3GetInt64", ".xxxx"),
        ("fmi3GetUInt64", ".xxxx"),
        ("fmi3GetBoolean", ".xxxx"),
        ("fmi3GetString", ".xxxx"),
        ("fmi3SetFloat64", "xxx.."),
        ("fmi3SetInt32", "xxx.."),
        ("fmi3SetInt64", "xxx.."),
        ("fmi3SetUInt64", "xxx.."),
        ("fmi3SetBoolean", "xxx.."),
        ("fmi3SetString", "xxx.."),
        ("fmi3GetFMUState", "xxxxx"),
        ("fmi3DoStep", "..x.."),
    ];

    fn column(p: Phase) -> usize {
        match p {
            Instantiated => 0,
            InitializationMode => 1,
            StepComplete => 2,
            Terminated => 3,
            Error => 4,
        }
    }

    #[test]
    fn each_fmi3_function_is_allowed_where_its_instance_operation_is() {
        for ((name, op), (std_name, row)) in MAPPED.iter().zip(STANDARD3) {
            assert_eq!(*name, std_name);
            for p in Phase::ALL {
                assert_eq!(
                    op.allowed().contains(p),
                    row.as_bytes()[column(p)] == b'x',
                    "{name} in {p:?}"
                );
            }
        }
    }

    #[test]
    fn messages_speak_fmi3() {
        assert_eq!(
            in_fmi3_terms("fmi2GetReal: Illegal call sequence (state StepComplete)"),
            "fmi3GetFloat64: Illegal call sequence (state StepMode)"
        );
        assert_eq!(
            in_fmi3_terms("fmi2SerializedFMUstateSize and fmi2SerializeFMUstate; fmi2DoStep"),
            "fmi3SerializedFMUStateSize and fmi3SerializeFMUState; fmi3DoStep"
        );
        assert!(!in_fmi3_terms("fmi2Instantiate: GUID 'x'").contains("fmi2"));
    }
}
