//! The 34 FMI 2.0 co-simulation functions and, in [`fmi3`], the 75 FMI 3.0 functions: the only
//! `unsafe` and the only exported symbols.
//!
//! Every entry point checks its pointers, bounds every length and count it is given before it
//! reads or allocates by it ([`crate::limits`]), runs the call under [`panic_hook::guarded`] (a panic
//! becomes `fmi2Error` with its message and location logged through the instance's logger, and
//! nothing reaches stderr), and reaches the instance through the registry of live instances
//! (`registry.rs`: an `fmi2Component` is a token, never dereferenced, so null, foreign and freed
//! ones are refused and `fmi2FreeInstance` is safe against a concurrent call) and a per-instance
//! mutex (`try_lock`: a second thread calling the same instance at the same time gets `fmi2Error`
//! and a logged reason instead of a data race). Messages go only to the FMI logger callback, with
//! `%` escaped as `%%` (the logger is printf-like). The process-wide state is the panic hook
//! ([`panic_hook`]) and the registry.

#![allow(non_snake_case)]

mod args;
mod binding;
mod common;
mod cosim;
pub mod fmi3;
mod fmu_state;
mod inner;
mod logger;
pub mod panic_hook;
mod registry;
mod types;
mod values;

pub use common::*;
pub use cosim::*;
pub use fmi3::*;
pub use fmu_state::*;
pub use registry::live_instances;
pub use types::{CallbackFunctions, Logger3Fn, LoggerFn};
pub use values::*;
