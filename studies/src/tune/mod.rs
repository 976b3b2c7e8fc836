//! Filter tuning (`entrynav tune`): the search ([`search`], Nelder–Mead over log₁₀ factors with
//! common random numbers) on a scenario's entry filters ([`entry`], its factors in [`groups`]),
//! one filter at a time ([`filter`]); the study ([`study`]) that validates the answer on fresh runs ([`verdict`]) and
//! gives the input scenario's own text with the tunings written in ([`tuned_file`], with the
//! comments of [`comment`] and the figures of [`figures`]); its options ([`options`]).

pub mod comment;
pub mod entry;
pub mod figures;
pub mod filter;
pub mod groups;
pub mod options;
pub mod search;
pub mod study;
pub mod tuned_file;
pub mod verdict;

pub use entry::{EntryTuning, ParameterGroup};
pub use filter::{TunedFactor, TunedFilter};
pub use options::TuneStudyOptions;
pub use search::{Measured, TuneObjective, TuneOptions, TuneResult, TuningProblem, tune};
pub use study::{TuneStudy, run_tune};
