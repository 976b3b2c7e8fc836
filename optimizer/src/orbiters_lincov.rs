//! `optimize orbiters --objective lincov-*`: the bound-optimal constellation polished on the
//! position RMSE LinCov predicts for the filter ([`LinCovScore`]).
//!
//! As for ground sites ([`crate::ground::GroundLinCovSolution`]), one LinCov is too costly for
//! the global search, which runs on the nominal bound of the same figure
//! ([`OrbiterNavProblem::optimize`]); its optimum starts a restarted Nelder–Mead over
//! (Ω, i, f) per orbiter on the LinCov score. Hidden orbiters give no measurements, so, as for
//! the bound, no visibility penalty is needed.

use crate::error::OptimizerError;
use crate::lincov_score::{LinCovFigures, LinCovScore};
use crate::orbiters::OrbitElements;
use crate::orbiters_nav::OrbiterNavProblem;
use crate::output::{BeaconNoise, orbiter_beacons};
use crate::progress::Progress;
use crate::search::polish_from;
use crate::search_options::{SearchOptions, SearchResult};
use std::time::Instant;

/// The LinCov-polished constellation.
#[derive(Debug, Clone)]
pub struct OrbiterLinCovSolution {
    /// Canonical elements.
    pub elements: Vec<OrbitElements>,
    /// LinCov's figures at `elements`.
    pub figures: LinCovFigures,
    /// The objective's value at `elements`.
    pub value: f64,
    /// LinCov's figures at the bound optimum the polish started from.
    pub start_figures: LinCovFigures,
    /// Polish statistics (cost: log10 of the value).
    pub search: SearchResult,
    /// Wall time of the polish \[s\].
    pub elapsed_s: f64,
}

impl OrbiterNavProblem {
    /// Polish `start` (the bound search's optimum) on `score`, the orbiters carrying `noise`.
    pub fn polish_on_lincov(
        &self,
        score: &LinCovScore,
        start: &[OrbitElements],
        noise: &BeaconNoise,
        opts: &SearchOptions,
        progress: Progress<'_>,
    ) -> Result<OrbiterLinCovSolution, OptimizerError> {
        let started = Instant::now();
        let geometry = self.geometry();
        let altitude = geometry.altitude_m();
        let beacons = |el: &[OrbitElements]| orbiter_beacons(el, altitude, noise);
        let (lower, upper) = geometry.bounds();
        let x0: Vec<f64> = start
            .iter()
            .flat_map(|e| [e.raan, e.inc, e.true_anomaly])
            .collect();
        let start_figures = score.figures(beacons(start))?;
        let cost = |x: &[f64]| score.cost(beacons(&geometry.elements_from(x)));
        let search = polish_from(&cost, &x0, &lower, &upper, opts, progress)?;
        let elements: Vec<OrbitElements> = geometry
            .elements_from(&search.x)
            .iter()
            .map(OrbitElements::canonical)
            .collect();
        let figures = score.figures(beacons(&elements))?;
        let value = score.value_of(&figures)?;
        Ok(OrbiterLinCovSolution {
            elements,
            figures,
            value,
            start_figures,
            search,
            elapsed_s: started.elapsed().as_secs_f64(),
        })
    }
}
