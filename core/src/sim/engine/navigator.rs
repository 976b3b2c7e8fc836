//! [`Navigator`]: a navigation filter fed with measurement epochs, with the estimate and status
//! the FMUs expose and the Monte Carlo records. It holds the filter and the [`Onboard`] view it
//! was built from, never the truth; [`Navigator::judge`] is given the truth from outside.

use super::filter::{ErasedFilter, FilterFailure, Judgement, NavEstimate, build_erased};
use super::truth::{TruthSample, truth_sample};
use super::truth_sensors::truth_draw;
use super::{EngineError, StepReport, check_step};
use crate::estimation::Onboard;
use crate::estimation::nav::{FilterKind, StepInfo};
use crate::scenario::{Scenario, TruthDraw};
use crate::sensors::MeasurementEpoch;
use crate::sim::start::initial_estimate;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use std::sync::Arc;

/// Filter health.
#[derive(Debug, Clone, PartialEq)]
pub enum NavStatus {
    /// No measurement epoch processed yet (the estimate is the filter start).
    Initial,
    /// Processing epochs.
    Running,
    /// Stopped on a numerical failure at `t`; the estimate holds its last good value.
    Failed {
        /// Epoch of the failure \[s\].
        t: f64,
        /// What failed.
        reason: FilterFailure,
    },
}

impl NavStatus {
    /// Integer code: 0 initial, 1 running, 2 failed.
    pub fn code(&self) -> i32 {
        match self {
            NavStatus::Initial => 0,
            NavStatus::Running => 1,
            NavStatus::Failed { .. } => 2,
        }
    }
}

/// A navigation filter fed with measurement epochs: the engine's navigation step.
pub struct Navigator {
    onboard: Arc<Onboard>,
    kind: FilterKind,
    filter: Box<dyn ErasedFilter>,
    estimate: NavEstimate,
    status: NavStatus,
    time: f64,
    last_epoch_t: f64,
}

impl std::fmt::Debug for Navigator {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Navigator")
            .field("scenario", &self.onboard.scenario_name)
            .field("kind", &self.kind)
            .field("time", &self.time)
            .field("status", &self.status)
            .finish()
    }
}

impl Navigator {
    /// Filter `kind` on the `onboard` view, started at the initial estimate `x0` (the nominal
    /// start is `onboard.initial_estimate`).
    pub fn new(onboard: Arc<Onboard>, kind: FilterKind, x0: &[f64]) -> Result<Self, EngineError> {
        kind.check_fits(&onboard)?;
        Self::new_checked(onboard, kind, x0)
    }

    /// [`Navigator::new`] for a filter already checked to fit (a Monte Carlo checks once). The
    /// filter is built from `onboard.for_filter(kind)`: with its own tuning when it has one.
    pub(crate) fn new_checked(
        onboard: Arc<Onboard>,
        kind: FilterKind,
        x0: &[f64],
    ) -> Result<Self, EngineError> {
        let onboard = onboard.for_filter(kind);
        let filter = build_erased(kind, &onboard, x0)?;
        let estimate = filter.estimate(0.0, StepInfo::default());
        Ok(Navigator {
            onboard,
            kind,
            filter,
            estimate,
            status: NavStatus::Initial,
            time: 0.0,
            last_epoch_t: 0.0,
        })
    }

    /// Filter `kind` on `scenario`, started as the combined engine starts it for `seed` and
    /// `dispersed` (the scenario's `filter.initial`, or with `filter.sample_initial_from_p0` a draw
    /// around the seed's truth realisation at t = 0 from the seed's stream 1).
    pub fn for_seed(
        scenario: &Scenario,
        kind: FilterKind,
        seed: u64,
        dispersed: bool,
    ) -> Result<Self, EngineError> {
        let (draw, _) = truth_draw(scenario, seed, dispersed);
        let t0 = truth_sample(scenario, &draw, 0.0, &draw.initial, scenario.truth_bank);
        Self::for_truth(scenario, kind, seed, &draw, &t0)
    }

    /// As [`Navigator::for_seed`] with the truth realisation `draw` and its sample `t0` at t = 0.
    pub(super) fn for_truth(
        scenario: &Scenario,
        kind: FilterKind,
        seed: u64,
        draw: &TruthDraw,
        t0: &TruthSample,
    ) -> Result<Self, EngineError> {
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        rng.set_stream(1);
        let x0 = initial_estimate(scenario, draw, t0, &mut rng);
        Self::new(Arc::clone(&scenario.onboard), kind, &x0)
    }

    /// The onboard view the filter was built from.
    pub fn onboard(&self) -> &Arc<Onboard> {
        &self.onboard
    }

    /// The filter.
    pub fn kind(&self) -> FilterKind {
        self.kind
    }

    /// Filter state dimension.
    pub fn state_dim(&self) -> usize {
        self.estimate.x.len()
    }

    /// The latest estimate (at its epoch time `estimate().t`).
    pub fn estimate(&self) -> &NavEstimate {
        &self.estimate
    }

    /// Filter health.
    pub fn status(&self) -> &NavStatus {
        &self.status
    }

    /// Current communication point \[s\].
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Set the bank-angle command \[rad\] the filter's onboard models use from now on (the filter
    /// starts with the onboard initial bank).
    pub fn set_bank_angle(&mut self, bank: f64) -> Result<(), EngineError> {
        if !bank.is_finite() {
            return Err(EngineError::NonFiniteInput("bank angle"));
        }
        self.filter.set_bank_angle(bank);
        Ok(())
    }

    /// Process one measurement epoch (predict to `epoch.t`, update). Epochs at or before the last
    /// processed one are ignored (a master holding its inputs over several steps), and so is every
    /// epoch after a filter failure. Returns whether the epoch was processed.
    pub fn process(&mut self, epoch: &MeasurementEpoch) -> bool {
        if matches!(self.status, NavStatus::Failed { .. })
            || epoch.t <= self.last_epoch_t
            || !epoch.t.is_finite()
        {
            return false;
        }
        self.last_epoch_t = epoch.t;
        let beacons = self.onboard.beacon_states(epoch.t);
        match self.filter.step(epoch, &beacons) {
            Ok(info) => {
                self.estimate = self.filter.estimate(epoch.t, info);
                self.status = NavStatus::Running;
            }
            Err(reason) => {
                self.status = NavStatus::Failed { t: epoch.t, reason };
            }
        }
        true
    }

    /// Advance from `t` by `h` with bank-angle command `bank` \[rad\], processing `epoch`
    /// (measurements taken at `epoch.t ≤ t + h`) if it is newer than the last one processed. The
    /// filter uses `bank` from this step on (prediction to the epoch included).
    pub fn do_step(
        &mut self,
        t: f64,
        h: f64,
        bank: f64,
        epoch: Option<&MeasurementEpoch>,
    ) -> Result<StepReport, EngineError> {
        check_step(self.time, t, h)?;
        if !bank.is_finite() {
            return Err(EngineError::NonFiniteInput("bank angle"));
        }
        let mut report = StepReport::default();
        if let Some(e) = epoch
            && e.values.iter().flatten().any(|v| !v.is_finite())
        {
            return Err(EngineError::NonFiniteInput("measurement"));
        }
        self.filter.set_bank_angle(bank);
        if let Some(e) = epoch {
            if e.t <= t + h + 1e-9 && self.process(e) {
                report.epochs = 1;
            }
        }
        self.time = t + h;
        Ok(report)
    }

    /// Move the communication point to `t` (the combined engine, which steps the filter itself).
    pub(super) fn set_time(&mut self, t: f64) {
        self.time = t;
    }

    /// The current estimate judged against the truth `sample` of the realisation `draw`.
    pub fn judge(&self, scenario: &Scenario, draw: &TruthDraw, sample: &TruthSample) -> Judgement {
        self.filter.judge(scenario, draw, sample)
    }
}
