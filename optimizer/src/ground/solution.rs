//! What the ground search gives: the objective and constraints at one set of sites
//! ([`GroundEvaluation`]) and an optimized set ([`GroundSolution`]).

use super::site::Site;
use crate::search_options::SearchResult;

/// The objective and constraint data at one set of sites.
#[derive(Debug, Clone, PartialEq)]
pub struct GroundEvaluation {
    /// Objective value (units: [`GroundObjective::units`](super::GroundObjective::units)); `None` when infeasible.
    pub value: Option<f64>,
    /// Search cost.
    pub cost: f64,
    /// Smallest elevation of the vehicle seen from each site over the trajectory \[rad\].
    pub min_elevation_rad: Vec<f64>,
    /// The smallest great-circle separation between two sites \[rad\] (`None`: one site).
    pub closest_pair_rad: Option<f64>,
    /// Every site meets the elevation requirement and the minimum separation.
    pub feasible: bool,
}

/// An optimized set of sites.
#[derive(Debug, Clone, PartialEq)]
pub struct GroundSolution {
    /// Canonical sites.
    pub sites: Vec<Site>,
    /// The objective at these sites.
    pub evaluation: GroundEvaluation,
    /// Search statistics.
    pub search: SearchResult,
    /// Wall time of the search \[s\].
    pub elapsed_s: f64,
}
