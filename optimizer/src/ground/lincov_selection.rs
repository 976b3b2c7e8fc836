//! `optimize select --objective lincov-nav|lincov-avg|lincov-final`: the bound's selection
//! ([`GroundProblem::select_on_bound`]) improved by exchanges scored by LinCov of the filter
//! ([`LinCovScore`]).
//!
//! Each round evaluates every exchange of one chosen site for an unchosen candidate that keeps
//! the minimum separation (k × (m − k) LinCovs, in parallel on rayon's pool, collected in order),
//! and applies the best one that improves the LinCov value; it stops when none does. Ties and the
//! order of evaluation cannot change the answer: the best is the lowest value, then the lowest
//! (slot, candidate) pair, whatever the thread count. Like the bound's, the answer is a local
//! optimum without certificate. A candidate set whose LinCov fails is skipped (never chosen).

use super::problem::GroundProblem;
use super::site::Site;
use crate::error::OptimizerError;
use crate::lincov_score::{LinCovFigures, LinCovScore};
use rayon::prelude::*;
use std::f64::consts::PI;

/// A selection improved on LinCov.
#[derive(Debug, Clone, PartialEq)]
pub struct LinCovSelection {
    /// Indices of the chosen candidates, ascending.
    pub indices: Vec<usize>,
    /// The LinCov objective at them.
    pub value: f64,
    /// LinCov's figures at them.
    pub figures: LinCovFigures,
    /// LinCov's figures at the bound's selection the exchanges started from.
    pub start_figures: LinCovFigures,
    /// LinCov evaluations used.
    pub evaluations: usize,
    /// Improving exchanges applied.
    pub exchanges: usize,
}

impl GroundProblem {
    /// Improve the selection `start` (indices into `candidates`) by exchanges on `score`.
    pub fn exchange_on_lincov(
        &self,
        candidates: &[Site],
        start: &[usize],
        score: &LinCovScore,
    ) -> Result<LinCovSelection, OptimizerError> {
        let beacons = |chosen: &[usize]| {
            let sites: Vec<Site> = chosen.iter().map(|&i| candidates[i]).collect();
            self.beacons_of(&sites)
        };
        let start_figures = score.figures(beacons(start))?;
        let mut value = score.value_of(&start_figures)?;
        let mut chosen = start.to_vec();
        let mut evaluations = 1usize;
        let mut exchanges = 0usize;
        let apart = |others: &[usize], j: usize| {
            others.iter().all(|&i| {
                Self::closest_pair(&[candidates[i], candidates[j]]).unwrap_or(PI)
                    >= self.min_separation
            })
        };
        loop {
            let k = chosen.len();
            let trials: Vec<(usize, usize)> = (0..k)
                .flat_map(|slot| {
                    let others: Vec<usize> =
                        (0..k).filter(|&s| s != slot).map(|s| chosen[s]).collect();
                    let chosen = &chosen;
                    (0..candidates.len())
                        .filter(move |&j| !chosen.contains(&j) && apart(&others, j))
                        .map(move |j| (slot, j))
                        .collect::<Vec<_>>()
                })
                .collect();
            let values: Vec<f64> = trials
                .par_iter()
                .map(|&(slot, j)| {
                    let mut trial = chosen.clone();
                    trial[slot] = j;
                    score
                        .figures(beacons(&trial))
                        .and_then(|f| score.value_of(&f))
                        .unwrap_or(f64::NAN)
                })
                .collect();
            evaluations += trials.len();
            let best = trials
                .iter()
                .zip(&values)
                .filter(|(_, v)| v.is_finite() && **v < value - 1e-12 * value.abs())
                .min_by(|a, b| a.1.total_cmp(b.1));
            let Some((&(slot, j), &v)) = best else { break };
            chosen[slot] = j;
            value = v;
            exchanges += 1;
        }
        let figures = score.figures(beacons(&chosen))?;
        chosen.sort_unstable();
        Ok(LinCovSelection {
            indices: chosen,
            value,
            figures,
            start_figures,
            evaluations,
            exchanges,
        })
    }
}
