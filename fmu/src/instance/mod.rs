//! A safe FMU instance: the FMI 2.0 co-simulation state machine, variable access and the engine.
//!
//! Every method checks the calling sequence first against the table of allowed states, one entry
//! per fmi2 function ([`Operation::allowed`]); an illegal call is answered with [`Status::Error`] and
//! the message "Illegal call sequence", and leaves the instance as it was. A *refused* call changes nothing either: a bad argument (unknown value
//! reference, a wrong type, NaN/Inf reals, a step at the wrong communication point or past the
//! stop time) or a request over a bound of [`crate::limits`]. A call that *starts and fails* —
//! fmi2ExitInitializationMode that cannot build the engine, a step in which the simulation
//! fails, fmi2SetFMUstate whose replay fails — moves the instance to the error state, from which
//! only fmi2Reset, fmi2SetFMUstate, fmi2FreeInstance and the queries lead on (FMI 2.0 §2.1.3).

mod allowed;
mod engine;
mod fmi3;
mod guidance;
mod guidance_error;
mod guided;
mod lifecycle;
mod machine;
mod outputs;
mod scenario;
mod snapshot;
mod spec;
mod status;
mod stepping;
mod values;

pub use allowed::{Operation, Phases};
pub use engine::{Engine, InstanceError};
pub use fmi3::{Ref3, Type3};
pub use guidance::{GuidanceEngine, GuidanceInputs, GuidanceReport, GuidanceStepError};
pub use guided::{GuidedEngine, GuidedReport, GuidedStatus};
pub use lifecycle::{StatusAnswer, StatusType};
pub use machine::Instance;
pub use scenario::{ScenarioFileError, load_resource_scenario};
pub use spec::{generic_spec, resolve_spec};
pub use status::{InstantiateError, LogSink, Status};
