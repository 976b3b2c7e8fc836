//! `trade compare`: two trade summaries compared filter by filter ([`study`]), from what a
//! summary holds ([`input`]), with the rows of one filter ([`filter`]), paired rows from the
//! per-run final errors ([`paired`]) and what differs between the two scenarios
//! ([`scenarios`]); the result's types in [`types`].

pub mod filter;
pub mod input;
pub mod paired;
pub mod scenarios;
pub mod study;
pub mod types;

pub use input::SummaryIn;
pub use paired::FinalErrors;
pub use study::compare_summaries;
pub use types::{Band, Comparison, FilterComparison, Row, Source};
