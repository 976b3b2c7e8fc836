//! One Monte Carlo run replayed in full: every epoch's truth, estimate, σ, error, NEES, per-channel
//! innovations and NIS, and fusion weights or model probabilities. `entrynav trade --replay-run K`
//! writes it as CSV to trace a failed or diverged run found in a study's `failures`.

use super::trade_error::TradeError;
use crate::estimation::nav::FilterKind;
use crate::scenario::Scenario;
use crate::sensors::MeasurementEpoch;
use crate::sim::engine::{FilterFailure, Judgement, Navigator, Observer, TruthSample, record_run};
use std::sync::Arc;

/// One epoch of a replayed filter.
#[derive(Debug, Clone, PartialEq)]
pub struct ReplayEpoch {
    /// Epoch time \[s\].
    pub t: f64,
    /// Truth in filter coordinates (truth-equivalent augmented values; NaN where none).
    pub truth: Vec<f64>,
    /// Estimate.
    pub estimate: Vec<f64>,
    /// 1σ per state.
    pub sigma: Vec<f64>,
    /// Error x̂ − x.
    pub err: Vec<f64>,
    /// NEES over every state with a truth value, with its dof.
    pub nees: Option<(f64, usize)>,
    /// NEES over the kinematic states.
    pub nees_kinematic: Option<f64>,
    /// Position and velocity error norms \[m\], [m/s].
    pub pos_vel_err: (f64, f64),
    /// NIS of the update.
    pub nis: Option<f64>,
    /// Per scalar measurement: channel slot, innovation (when the filter reports it) and ν²/s.
    pub channels: Vec<(usize, Option<f64>, f64)>,
    /// Fusion weights or model probabilities.
    pub weights: Option<Vec<f64>>,
}

/// A filter's whole run.
#[derive(Debug, Clone, PartialEq)]
pub struct Replay {
    /// Filter name.
    pub filter: String,
    /// Every epoch processed.
    pub epochs: Vec<ReplayEpoch>,
    /// Numerical failure, if any: (time, reason).
    pub failure: Option<(f64, String)>,
}

/// The observer that keeps every epoch of a flight in full.
impl Observer for Replay {
    fn epoch(
        &mut self,
        nav: &Navigator,
        epoch: &MeasurementEpoch,
        _sample: &TruthSample,
        j: Judgement,
    ) {
        let est = nav.estimate();
        let info = &est.info;
        let aligned = info.innovations.len() == info.nis_terms.len();
        self.epochs.push(ReplayEpoch {
            t: epoch.t,
            truth: j.truth,
            estimate: est.x.clone(),
            sigma: est.sigma.clone(),
            err: j.err,
            nees: j.nees,
            nees_kinematic: j.nees_kinematic,
            pos_vel_err: j.pos_vel_err,
            nis: info.nis,
            channels: info
                .nis_terms
                .iter()
                .enumerate()
                .map(|(i, &(c, v))| (c, aligned.then(|| info.innovations[i]), v))
                .collect(),
            weights: info.weights.clone(),
        });
    }

    fn failure(&mut self, t: f64, reason: &FilterFailure) {
        self.failure = Some((t, reason.to_string()));
    }
}

/// Replay run `run` of the study (`scenario`, `filters`, `seed`): the same truth, noise and start
/// as in the study.
pub fn replay_run(
    scenario: &Arc<Scenario>,
    filters: &[FilterKind],
    seed: u64,
    run: usize,
) -> Result<Vec<Replay>, TradeError> {
    for f in filters {
        f.check_fits(&scenario.onboard)?;
    }
    let rec = record_run(scenario, seed, run)?;
    let mut out = Vec::with_capacity(filters.len());
    for &kind in filters {
        let mut replay = Replay {
            filter: kind.name().to_string(),
            epochs: Vec::new(),
            failure: None,
        };
        match Navigator::new(Arc::clone(&scenario.onboard), kind, &rec.x0) {
            Ok(mut nav) => {
                nav.fly(scenario, &rec, &mut replay);
            }
            Err(e) => replay.failure = Some((0.0, e.to_string())),
        }
        out.push(replay);
    }
    Ok(out)
}
