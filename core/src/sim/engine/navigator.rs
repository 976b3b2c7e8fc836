//! [`Navigator`]: a navigation filter fed with measurement epochs, with the estimate and status
//! the FMUs expose and the Monte Carlo records. It holds the filter and the [`Onboard`] view it
//! was built from, never the truth; [`Navigator::judge`] is given the truth from outside.

use super::error::EngineError;
use super::filter::{ErasedFilter, FilterFailure, Judgement, NavEstimate, build_erased};
use super::start::initial_estimate;
use super::step_check::check_step;
use super::truth::{TruthSample, truth_sample};
use super::truth_sensors::StepReport;
use super::truth_sensors::truth_draw;
use crate::estimation::Onboard;
use crate::estimation::nav::{FilterKind, StepInfo};
use crate::scenario::{Scenario, TruthDraw};
use crate::sensors::MeasurementEpoch;
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
    /// Bank commands not yet flown by the filter: (communication point from which it is flown
    /// \[s\], bank \[rad\]), in time order, each different from the one before.
    pending_banks: Vec<(f64, f64)>,
    /// Start of the previous [`Navigator::do_step`] (the step whose bank the next one is given).
    previous_step_start: Option<f64>,
}

/// Most bank changes held for epochs still to come; beyond it the oldest becomes the filter's
/// bank from its current time (a master that never sends measurements must not grow memory
/// without bound; the bank history before the next epoch is then approximate).
const MAX_PENDING_BANKS: usize = 1024;

/// Two times closer than this are the same instant \[s\] (as the engine's step checks).
const SAME_INSTANT_S: f64 = 1e-9;

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
            pending_banks: Vec::new(),
            previous_step_start: None,
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

    /// Command bank `bank` \[rad\] from the current communication point on (the filter starts with
    /// the onboard initial bank). The filter flies each command over the time it was in force: a
    /// prediction to an epoch that spans several commands is made piecewise, each piece with its
    /// own bank (module documentation, "Bank angle"). Setting the bank in force changes nothing.
    pub fn set_bank_angle(&mut self, bank: f64) -> Result<(), EngineError> {
        if !bank.is_finite() {
            return Err(EngineError::NonFiniteInput("bank angle"));
        }
        self.command_bank(self.time, bank);
        Ok(())
    }

    /// Record bank `bank` in force from `t` (the communication point the master gave).
    pub(super) fn command_bank(&mut self, t: f64, bank: f64) {
        if matches!(self.status, NavStatus::Failed { .. }) {
            return;
        }
        let in_force = self
            .pending_banks
            .last()
            .map_or_else(|| self.filter.bank_angle(), |&(_, b)| b);
        if bank == in_force {
            return;
        }
        match self.pending_banks.last_mut() {
            // A second command at the same point replaces the first.
            Some(last) if last.0 == t => last.1 = bank,
            _ => self.pending_banks.push((t, bank)),
        }
        // A replacement may have restored the bank before it: drop the no-op entry.
        let n = self.pending_banks.len();
        let before = if n >= 2 {
            self.pending_banks[n - 2].1
        } else {
            self.filter.bank_angle()
        };
        if self.pending_banks[n - 1].1 == before {
            self.pending_banks.pop();
        }
        if self.pending_banks.len() > MAX_PENDING_BANKS {
            // No epoch for that many commands: the oldest is flown from the filter's own time
            // (not predicted to, which a master that sends no measurements never asked for).
            let (_, oldest) = self.pending_banks.remove(0);
            self.filter.set_bank_angle(oldest);
        }
    }

    /// Fly the pending bank commands that start before `t`: predict to each one's start with the
    /// bank before it, then switch. The filter is left at the latest such start (or where it was)
    /// with the bank in force just before `t`.
    fn fly_banks_before(&mut self, t: f64) -> Result<(), FilterFailure> {
        let mut flown = 0;
        for &(t_from, bank) in &self.pending_banks {
            if t_from >= t {
                break;
            }
            // A start within 1 ns of the filter's time is that time (communication points
            // accumulated in floating point), not a prediction of 1e-16 s.
            if t_from > self.filter.time() + SAME_INSTANT_S {
                self.filter.predict_to(t_from)?;
            }
            self.filter.set_bank_angle(bank);
            flown += 1;
        }
        self.pending_banks.drain(..flown);
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
        if let Err(reason) = self.fly_banks_before(epoch.t) {
            self.status = NavStatus::Failed { t: epoch.t, reason };
            return true;
        }
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
    /// (measurements taken at `epoch.t ≤ t + h`) if it is newer than the last one processed.
    /// `bank` is the bank the truth flew over the *previous* step (the FMUs' one-step-late wiring,
    /// the truth's `truth_bank_angle` output, as the epoch is that step's): the filter flies it
    /// from the previous step's start (from `t` at the first step), piecewise with the others
    /// ([`Navigator::set_bank_angle`]).
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
        // The bank the truth flew over the previous step (the one-step-late wiring): flown from
        // that step's start.
        self.command_bank(self.previous_step_start.unwrap_or(t), bank);
        self.previous_step_start = Some(t);
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
