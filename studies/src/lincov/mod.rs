//! LinCov of navigation filters along the nominal trajectory ([`analysis`]), the study of
//! `entrynav lincov` with an optional Monte Carlo beside it ([`study`]) and what it writes
//! ([`document`]).

pub mod analysis;
pub mod document;
pub mod study;

pub use analysis::{Analysed, analyse, mean_error_nees, parse_filters};
pub use study::{LinCovStudy, LinCovStudyOptions, MAX_COMPARE_RUNS, run_lincov};
