//! Choosing k of m candidate sites on the nominal position bound (`optimize select --objective
//! nav|pcrlb-avg|pcrlb-final`): greedy, then the best single exchange of a chosen and an unchosen
//! site while one improves, every pair at least the minimum separation apart.
//!
//! The bound is not concave in the selection, so unlike the convex criteria of
//! [`crate::select`] there is no relaxation bound and no certificate: the answer is a local
//! optimum (no exchange improves it), and the search says so.

use super::objective::GroundObjective;
use super::problem::GroundProblem;
use super::site::Site;
use crate::error::OptimizerError;
use std::f64::consts::PI;

/// A selection on the bound.
#[derive(Debug, Clone, PartialEq)]
pub struct BoundSelection {
    /// Indices of the chosen candidates, ascending.
    pub indices: Vec<usize>,
    /// The objective at them.
    pub value: f64,
    /// Bound evaluations used.
    pub evaluations: usize,
    /// Exchange rounds that improved the selection.
    pub exchanges: usize,
}

impl GroundProblem {
    /// Choose `k` (the problem's count) of `candidates` minimising the problem's bound objective
    /// (greedy from the empty set, then exchanges). Pairs closer than the minimum separation are
    /// never chosen together.
    pub fn select_on_bound(&self, candidates: &[Site]) -> Result<BoundSelection, OptimizerError> {
        if !self.objective.is_bound() {
            return Err(OptimizerError::InvalidInput(format!(
                "selection on the bound needs a bound objective, not {}",
                self.objective.name()
            )));
        }
        let k = self.count;
        if candidates.len() < k {
            return Err(OptimizerError::Infeasible(format!(
                "{} candidate(s) for {k} sites",
                candidates.len()
            )));
        }
        let mut evaluations = 0usize;
        let mut value_of = |chosen: &[usize]| -> Result<f64, OptimizerError> {
            evaluations += 1;
            let sites: Vec<Site> = chosen.iter().map(|&i| candidates[i]).collect();
            let s = self.bound_series_of(&sites)?;
            Ok(match (self.objective, self.reference) {
                (GroundObjective::PcrlbAvg, _) => s.time_avg(),
                (GroundObjective::PcrlbFinal, _) => s.final_value(),
                (_, Some((avg, last))) => 0.5 * (s.time_avg() / avg + s.final_value() / last),
                (_, None) => {
                    return Err(OptimizerError::InvalidInput(
                        "the navigation objective needs the input design (with_reference)".into(),
                    ));
                }
            })
        };
        let apart = |chosen: &[usize], j: usize| {
            chosen.iter().all(|&i| {
                Self::closest_pair(&[candidates[i], candidates[j]]).unwrap_or(PI)
                    >= self.min_separation
            })
        };
        let mut chosen: Vec<usize> = Vec::with_capacity(k);
        let mut value = f64::INFINITY;
        for _ in 0..k {
            let mut best: Option<(f64, usize)> = None;
            for j in 0..candidates.len() {
                if chosen.contains(&j) || !apart(&chosen, j) {
                    continue;
                }
                let mut trial = chosen.clone();
                trial.push(j);
                let v = value_of(&trial)?;
                if best.is_none_or(|(b, _)| v < b) {
                    best = Some((v, j));
                }
            }
            let (v, j) = best.ok_or_else(|| {
                OptimizerError::Infeasible(format!(
                    "no {k} candidates are {:.3} deg apart",
                    self.min_separation.to_degrees()
                ))
            })?;
            chosen.push(j);
            value = v;
        }
        let mut exchanges = 0;
        loop {
            let mut best: Option<(f64, usize, usize)> = None;
            for slot in 0..k {
                let others: Vec<usize> = (0..k).filter(|&s| s != slot).map(|s| chosen[s]).collect();
                for j in 0..candidates.len() {
                    if chosen.contains(&j) || !apart(&others, j) {
                        continue;
                    }
                    let mut trial = chosen.clone();
                    trial[slot] = j;
                    let v = value_of(&trial)?;
                    if v < value - 1e-12 * value.abs() && best.is_none_or(|(b, _, _)| v < b) {
                        best = Some((v, slot, j));
                    }
                }
            }
            let Some((v, slot, j)) = best else { break };
            chosen[slot] = j;
            value = v;
            exchanges += 1;
        }
        chosen.sort_unstable();
        Ok(BoundSelection {
            indices: chosen,
            value,
            evaluations,
            exchanges,
        })
    }
}
