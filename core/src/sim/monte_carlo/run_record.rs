//! What one filter records over one Monte Carlo run: an [`Observer`] of the engine's loop
//! ([`Navigator::fly`]) that keeps, per epoch, the error, σ, NEES, NIS terms, density errors and
//! weights the accumulators of [`super::metrics`] fold, and [`filter_run`], which flies a filter
//! over a recorded run with it.

use super::exclusions::{JudgedExclusion, judge_exclusions};
use crate::estimation::Onboard;
use crate::estimation::nav::{FilterKind, GateReport};
use crate::scenario::Scenario;
use crate::sensors::MeasurementEpoch;
use crate::sim::engine::{FilterFailure, Judgement, Navigator, Observer, RecordedRun, TruthSample};
use std::sync::Arc;

/// What one filter produced at one epoch of one run.
#[derive(Debug, Clone, PartialEq)]
pub struct EpochRecord {
    /// Estimation error per state (NaN where the state has no truth).
    pub err: Vec<f64>,
    /// Predicted 1σ per state.
    pub sigma: Vec<f64>,
    /// Position error norm \[m\] and velocity error norm [m/s].
    pub pos_vel_err: (f64, f64),
    /// Position error in the local frame at the truth \[m\]: downrange (along the true heading),
    /// crossrange, up (radial).
    pub local_err: [f64; 3],
    /// NEES eᵀP⁻¹e over the states with truth, and its degrees of freedom.
    pub nees: Option<(f64, usize)>,
    /// NEES over the six kinematic states.
    pub nees_kinematic: Option<f64>,
    /// Per scalar measurement: channel slot and ν²/s.
    pub nis_terms: Vec<(usize, f64)>,
    /// Density relative error (ρ̂(h) − ρ(h))/ρ(h) of the filter's profile at the true altitude h,
    /// for filters that estimate density.
    pub density_rel_err: Option<f64>,
    /// Density relative error (ρ̂(x̂) − ρ(x))/ρ(x) at the filter's own estimate.
    pub density_at_estimate_rel_err: Option<f64>,
    /// Fusion weights / model probabilities.
    pub weights: Option<Vec<f64>>,
    /// What the innovation gate did (filters run with `[filter.gating]`).
    pub gate: Option<GateReport>,
}

/// Final-epoch quantities of one run.
#[derive(Debug, Clone, PartialEq)]
pub struct FinalRecord {
    /// Downrange and crossrange position error \[m\] (along / across the true heading).
    pub downrange_crossrange: (f64, f64),
}

/// Everything one filter produced in one run.
#[derive(Debug, Clone, PartialEq, Default)]
pub struct RunRecord {
    /// Per-epoch records, in time order.
    pub epochs: Vec<EpochRecord>,
    /// Epoch times \[s\].
    pub times: Vec<f64>,
    /// Final-epoch record (None if the filter failed).
    pub final_: Option<FinalRecord>,
    /// Numerical failure, if any: (time, reason).
    pub failure: Option<(f64, String)>,
    /// CPU time in the filter \[ns\] and steps.
    pub filter_ns: u128,
    /// Filter steps.
    pub steps: usize,
    /// The gate's beacon exclusions, judged against the truth's faults.
    pub exclusions: Vec<JudgedExclusion>,
}

impl Observer for RunRecord {
    fn epoch(
        &mut self,
        nav: &Navigator,
        epoch: &MeasurementEpoch,
        _sample: &TruthSample,
        j: Judgement,
    ) {
        let est = nav.estimate();
        self.times.push(epoch.t);
        self.final_ = Some(FinalRecord {
            downrange_crossrange: j.downrange_crossrange,
        });
        self.epochs.push(EpochRecord {
            err: j.err,
            sigma: est.sigma.clone(),
            pos_vel_err: j.pos_vel_err,
            local_err: [j.downrange_crossrange.0, j.downrange_crossrange.1, j.up_m],
            nees: j.nees,
            nees_kinematic: j.nees_kinematic,
            nis_terms: est.info.nis_terms.clone(),
            density_rel_err: j.density_profile_rel_err,
            density_at_estimate_rel_err: j.density_at_estimate_rel_err,
            weights: est.info.weights.clone(),
            gate: est.info.gate.clone(),
        });
    }

    fn failure(&mut self, t: f64, reason: &FilterFailure) {
        self.failure = Some((t, reason.to_string()));
        // A failed run has no deployment point.
        self.final_ = None;
    }
}

/// Filter `kind` built from `onboard` (the scenario's, or a re-tuned copy) flown over the
/// recorded run `recorded`, judged at every epoch against its truth.
pub fn filter_run(
    scenario: &Scenario,
    onboard: &Arc<Onboard>,
    recorded: &RecordedRun,
    kind: FilterKind,
) -> RunRecord {
    let mut rec = RunRecord::default();
    // One record per epoch: reserved up front rather than grown (and copied) as they arrive.
    let n_epochs = recorded.truth.epochs.len();
    rec.epochs.reserve_exact(n_epochs);
    rec.times.reserve_exact(n_epochs);
    let mut nav = match Navigator::new_checked(Arc::clone(onboard), kind, &recorded.x0) {
        Ok(nav) => nav,
        Err(e) => {
            rec.failure = Some((0.0, e.to_string()));
            return rec;
        }
    };
    let end = nav.fly(scenario, recorded, &mut rec);
    let events: Vec<_> = rec
        .epochs
        .iter()
        .filter_map(|e| e.gate.as_ref())
        .flat_map(|g| g.events.iter().copied())
        .collect();
    rec.exclusions = judge_exclusions(scenario, &events);
    rec.filter_ns = end.filter_ns;
    rec.steps = end.steps;
    rec
}
