//! Lower bounds on the estimation error: the posterior Cramér–Rao lower bound of a scenario
//! (Tichavský, Muravchik & Nehorai 1998; the recursion itself, plain matrix numerics, is
//! [`crate::pcrlb_recursion`]).
//!
//! * [`pcrlb`] — one truth run's bound inputs (F by the linearised STM along the run, the
//!   information by AD of the truth's measurement model), [`NoBound`] when the scenario has none;
//!   `pcrlb_epochs.rs` stores them compactly;
//! * [`pcrlb_sums`] — their sums over a study's runs, folded in run order, and the bound they
//!   give ([`PcrlbReport`]); [`pcrlb_study`] forms it from truth runs alone (`observe --pcrlb`);
//! * [`nominal_bound`] — the position bound along the nominal trajectory alone, for beacon
//!   design, where each candidate set of sites costs only the recursion.

pub mod nominal_bound;
pub mod nominal_bound_error;
mod nominal_epochs;
pub mod pcrlb;
mod pcrlb_epochs;
pub mod pcrlb_sums;

pub use nominal_bound::{NominalBound, NominalBoundSeries, RangeSite};
pub use nominal_bound_error::NominalBoundError;
pub use pcrlb::{BoundRun, NoBound, bound_run};
pub use pcrlb_epochs::BoundRunData;
pub use pcrlb_sums::{BoundSums, PcrlbReport, pcrlb_study};
