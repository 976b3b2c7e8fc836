//! The beacon and orbiter designs of seed 002 §4 (`entrynav optimize`), each checked against the
//! input design it improves on:
//!
//! * [`ground`] — surface-beacon sites visible during the whole entry
//!   ([`run_ground_design`], [`GroundOptions`] → [`GroundDesign`]);
//! * [`select`] — k of the candidate sites of a lat/lon grid, certified by the convex relaxation
//!   (Joshi & Boyd), proved by branch and bound, or chosen on the nominal bound
//!   ([`run_site_selection`], [`SelectOptions`] → [`SiteSelection`]);
//! * [`orbiters`] — relay orbiters on circular orbits ([`run_orbiter_design`],
//!   [`OrbiterOptions`] → [`OrbiterDesign`]).
//!
//! Shared: the named choices ([`choices`]), the search budget ([`search`]), the input design's
//! sites and elements ([`sites`]), the LinCov polish ([`lincov_stage`]), the Monte Carlo check of
//! every answer ([`check`]), the optimizer's progress ([`progress`]) and errors ([`failure`]).

pub mod check;
pub mod choices;
pub mod failure;
pub mod ground;
pub mod ground_options;
pub mod ground_result;
pub mod lincov_stage;
pub mod orbiters;
pub mod orbiters_options;
pub mod orbiters_result;
pub mod progress;
pub mod search;
pub mod select;
pub mod select_bound;
pub mod select_candidates;
pub mod select_exact;
pub mod select_json;
pub mod select_options;
pub mod select_result;
pub mod sites;

pub use check::DesignCheck;
pub use choices::SelectObjectiveName;
pub use choices::{Choice, Criterion, DeltaMethod, GroundObjectiveName, OrbiterObjectiveName};
pub use ground::run_ground_design;
pub use ground_options::GroundOptions;
pub use ground_result::GroundDesign;
pub use orbiters::run_orbiter_design;
pub use orbiters_options::OrbiterOptions;
pub use orbiters_result::OrbiterDesign;
pub use select::run_site_selection;
pub use select_options::SelectOptions;
pub use select_result::{SelectionAnswer, SiteSelection};
