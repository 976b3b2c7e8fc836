//! `optimize ground --objective lincov-*`: the bound's optimum polished on LinCov of the filter.
//!
//! The global search runs on the nominal position bound of the same figure (cheap); its optimum
//! starts a restarted Nelder–Mead ([`polish_from`]) whose cost is the position RMSE that LinCov
//! predicts for the filter with the candidate sites ([`LinCovScore`]). The constraints (eq. 52
//! visibility or the partial-visibility box, the minimum separation) are the bound search's:
//! an infeasible candidate costs the same graded penalty, so the polish never leaves the feasible
//! set for a better-looking score.

use super::penalty::INFEASIBLE_COST;
use super::problem::GroundProblem;
use super::site::Site;
use super::solution::GroundSolution;
use crate::error::OptimizerError;
use crate::lincov_score::{LinCovFigures, LinCovScore};
use crate::output::surface_beacons;
use crate::progress::Progress;
use crate::search::polish_from;
use crate::search_options::{SearchOptions, SearchResult};
use entrynav::beacons::BeaconConfig;
use std::time::Instant;

/// The polish budget on LinCov (one evaluation is tens of milliseconds): one start, 40
/// Nelder–Mead iterations per restarted round, a simplex edge of 1 % of the box.
pub fn default_lincov_polish(seed: u64) -> SearchOptions {
    SearchOptions {
        seed,
        starts: 1,
        particles: 2,
        iterations: 0,
        polish_iterations: 40,
        polish_step: 0.01,
    }
}

/// The LinCov-polished sites.
#[derive(Debug, Clone)]
pub struct GroundLinCovSolution {
    /// Canonical sites.
    pub sites: Vec<Site>,
    /// LinCov's figures at `sites`.
    pub figures: LinCovFigures,
    /// The objective's value at `sites`.
    pub value: f64,
    /// LinCov's figures at the bound optimum the polish started from.
    pub start_figures: LinCovFigures,
    /// Polish statistics (cost: log10 of the value, or the infeasibility penalty).
    pub search: SearchResult,
    /// Wall time of the polish \[s\].
    pub elapsed_s: f64,
}

impl GroundProblem {
    /// Surface-beacon entries for `sites` with the problem's range noise and elevation mask (what
    /// `--write-scenario` writes).
    pub fn beacons_of(&self, sites: &[Site]) -> Vec<BeaconConfig> {
        self.beacons_masked(sites, self.elevation_mask)
    }

    /// [`Self::beacons_of`] with elevation mask `mask_rad` (e.g. the input design's own).
    pub fn beacons_masked(&self, sites: &[Site], mask_rad: f64) -> Vec<BeaconConfig> {
        let mask_deg = mask_rad.to_degrees();
        let mut out = surface_beacons(sites, &self.noise);
        for b in &mut out {
            if let BeaconConfig::Surface(c) = b {
                c.elevation_mask_deg = (mask_deg > 0.0).then_some(mask_deg);
            }
        }
        out
    }

    /// The LinCov search cost at `x = [lat₁, lon₁, …]`: the bound search's penalty when the
    /// sites break a constraint, else the score's log10 value.
    pub fn lincov_cost(&self, score: &LinCovScore, x: &[f64]) -> f64 {
        let sites = self.sites_from(x);
        match self.evaluate(&sites) {
            Ok(e) if e.feasible => score.cost(self.beacons_of(&sites)),
            Ok(e) => e.cost,
            Err(_) => 2.0 * INFEASIBLE_COST,
        }
    }

    /// Polish `start` (the bound search's optimum) on `score`.
    pub fn polish_on_lincov(
        &self,
        score: &LinCovScore,
        start: &GroundSolution,
        opts: &SearchOptions,
        progress: Progress<'_>,
    ) -> Result<GroundLinCovSolution, OptimizerError> {
        let started = Instant::now();
        let (lower, upper) = self.bounds()?;
        let x0: Vec<f64> = start.sites.iter().flat_map(|s| [s.lat, s.lon]).collect();
        let start_figures = score.figures(self.beacons_of(&start.sites))?;
        let cost = |x: &[f64]| self.lincov_cost(score, x);
        let search = polish_from(&cost, &x0, &lower, &upper, opts, progress)?;
        let sites: Vec<Site> = self
            .sites_from(&search.x)
            .iter()
            .map(Site::canonical)
            .collect();
        if !self.evaluate(&sites)?.feasible {
            return Err(self.no_site_error());
        }
        let figures = score.figures(self.beacons_of(&sites))?;
        let value = score.value_of(&figures)?;
        Ok(GroundLinCovSolution {
            sites,
            figures,
            value,
            start_figures,
            search,
            elapsed_s: started.elapsed().as_secs_f64(),
        })
    }
}
