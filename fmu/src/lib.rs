//! FMI 2.0 co-simulation FMUs of entrynav.
//!
//! One shared library serves three FMUs; each `.fmu` carries a copy named after its model
//! identifier, and an instance learns which model it is from the GUID passed to `fmi2Instantiate`:
//! - `MarsEntryNav`: entry dynamics, sensors and navigation filter in one slave;
//! - `MarsEntryNavFilter`: the navigation filter alone, fed with measurements and validity flags;
//! - `MarsEntryTruth`: truth dynamics and sensors, whose measurement outputs have the same names as
//!   the filter FMU's inputs.
//!
//! Layers: [`vars`] (the variable table, shared with the XML generator, and the GUID), [`xml`]
//! (`modelDescription.xml`), [`state`] (FMU state snapshots and their byte format), [`instance`]
//! (a safe instance with the FMI state machine over `entrynav::sim::engine`), and `ffi` (the 34
//! exported `fmi2*` functions, the only unsafe code of the FMU itself). [`host`] is the other
//! side of the C ABI: our own FMI importer, used by `entrynav fmu check` and `fuzz` to drive a
//! packed `.fmu` through its exported functions.
#![warn(missing_docs)]

pub mod ffi;
pub mod host;
pub mod instance;
pub mod state;
pub mod uri;
pub mod vars;
pub mod xml;

pub use vars::{Model, guid_of};
pub use xml::model_description;
