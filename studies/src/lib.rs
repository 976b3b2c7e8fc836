//! The study layer of entrynav: every study a user runs — a trade (with grids, shards and merge,
//! and the statistics of `trade compare`), a tuning, a beacon or orbiter design with the check of
//! its answer, an observability analysis, LinCov, guided delivery, the FMU packages — as a
//! function of a scenario ([`scenario::ScenarioInput`]) and an options struct, returning a typed
//! result that serialises to the JSON the command line writes.
//!
//! A study never prints and has no exit codes: it reports progress through a callback
//! ([`progress`]) and ends with its result or a [`error::StudyError`] whose
//! [`kind`](error::StudyError::kind) each front end maps once (the `entrynav` command to its exit
//! code, the Python package to an exception). Options are checked here ([`options`]) before any
//! work starts, so both front ends refuse the same values with the same message.
//!
//! Layers (each imports only those above it): [`options`], [`progress`], [`error`], [`output`]
//! (files written whole or not at all, output paths checked up front), [`threads`],
//! [`provenance`], [`scenario`], [`statistics`] (sampling intervals of Monte Carlo figures), then
//! the studies.

pub mod compare;
pub mod design;
pub mod diagnosis;
pub mod error;
pub mod filters;
pub mod fmu_pack;
pub mod grid;
pub mod guidance;
pub mod input;
pub mod lincov;
pub mod observe;
pub mod options;
pub mod output;
pub mod progress;
pub mod provenance;
pub mod scenario;
pub mod simulate;
pub mod statistics;
pub mod threads;
pub mod trade;
pub mod tune;

pub use error::{ErrorKind, StudyError, StudyResult};
pub use scenario::ScenarioInput;
