//! Observability of a scenario (`entrynav observe`): the study ([`study`]: degree of
//! observability δ(t), range Fisher information, PCRLB), its options ([`options`]), its JSON
//! document ([`document`]) and the summary of its Fisher information ([`fim_summary`]).

pub mod document;
pub mod fim_summary;
pub mod options;
pub mod study;

pub use document::{RAW_NOTE, scaling_note};
pub use fim_summary::FimSummary;
pub use options::{MAX_PCRLB_RUNS, ObserveOptions};
pub use study::{FreeBeacons, Observation, PcrlbBound, run_observe};
