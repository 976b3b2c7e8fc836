//! What the orbiter search gives: the objective and visibility at one set of elements
//! ([`OrbiterEvaluation`]) and an optimized constellation ([`OrbiterSolution`]).

use super::elements::OrbitElements;
use crate::search_options::SearchResult;

/// The objective and its constraint data at one geometry.
#[derive(Debug, Clone, PartialEq)]
pub struct OrbiterEvaluation {
    /// Objective J (penalty-free; hidden orbiters contribute nothing).
    pub value: f64,
    /// Integrand at each trajectory sample (`det F` or `log max(det F, 10⁻⁹)`).
    pub integrand: Vec<f64>,
    /// Smallest visibility margin over orbiters and samples \[rad\] (> 0: all always visible).
    pub min_margin_rad: f64,
    /// `∫ Σ_j max(0, −m_j) dt` [rad·s].
    pub violation_rad_s: f64,
    /// Fraction of (orbiter, sample) pairs in line of sight.
    pub visible_fraction: f64,
    /// The cost the search minimises: `−J + c · violation`.
    pub cost: f64,
}

/// An optimized constellation.
#[derive(Debug, Clone, PartialEq)]
pub struct OrbiterSolution {
    /// Canonical elements of each orbiter.
    pub elements: Vec<OrbitElements>,
    /// The objective at these elements.
    pub evaluation: OrbiterEvaluation,
    /// Search statistics.
    pub search: SearchResult,
    /// Wall time of the search \[s\].
    pub elapsed_s: f64,
}
