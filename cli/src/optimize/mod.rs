//! `entrynav optimize`: beacon and orbiter geometry (seed 002 §4) — orbiters on circular orbits,
//! ground beacons visible during the whole entry, and the certified selection of k candidate
//! sites (Joshi & Boyd relaxation). The studies are `entrynav_studies::design`; this module
//! parses the arguments ([`args`]), runs each problem ([`command`]: [`ground`], [`select`],
//! [`orbiters`]) and prints its tables ([`tables`]), bars ([`progress_bars`]) and files
//! ([`files`]).

mod args;
mod command;
mod files;
mod ground;
mod orbiters;
mod progress_bars;
mod select;
mod tables;

pub use args::OptimizeArgs;
pub use command::run;
