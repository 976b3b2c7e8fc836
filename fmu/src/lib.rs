//! FMI 2.0 and FMI 3.0 co-simulation FMUs of entrynav.
//!
//! One shared library serves every model; `entrynav fmu pack` binds each packed copy to its own
//! model ([`binding`]), so a `.fmu` accepts only its model's GUID:
//! - `MarsEntryNav`: entry dynamics, sensors and navigation filter in one slave;
//! - `MarsEntryNavFilter`: the navigation filter alone, fed with measurements and validity flags;
//! - `MarsEntryTruth`: truth dynamics and sensors, whose measurement outputs have the same names as
//!   the filter FMU's inputs;
//! - `MarsEntryGuidance`: the scenario's `[guidance]` and its bank actuator, fed with the
//!   navigation estimate and the accelerometer triad (the inputs named as those FMUs' outputs);
//! - `MarsEntryNav_<scenario>`: the combined model with one scenario embedded, whose state outputs
//!   carry the scenario's state names and units.
//!
//! Layers: [`vars`] (the variable table, shared with the XML generator, and the GUID), [`xml`]
//! (`modelDescription.xml`), [`state`] (FMU state snapshots and their byte format), [`limits`]
//! (the bound on everything from outside), [`instance`] (a safe instance with the FMI state
//! machine over `entrynav::sim::engine`, and its allowed-state table), [`xml3`] (the FMI 3.0
//! description of the same table plus [`vars::fmi3`]), and [`ffi`] (the 34 exported `fmi2*` and
//! 75 `fmi3*` functions and the registry of live instances, the only unsafe code). The
//! other side of the C ABI, our own FMI importer used by the developer tools (`entrynav-dev fmu
//! check` and `fuzz`), is the `entrynav-fmi-host` crate, so this library carries only the FMU.
#![warn(missing_docs)]

pub mod binding;
pub mod ffi;
pub mod instance;
pub mod limits;
pub mod state;
pub mod uri;
pub mod vars;
pub mod xml;
pub mod xml3;

pub use vars::{Model, ModelSpec, guid_of};
pub use xml::{description_of, model_description};
pub use xml3::{Arrays, description3_of};
