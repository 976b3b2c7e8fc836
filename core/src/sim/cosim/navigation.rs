//! [`NavigationCoSim`]: a navigation filter alone, fed with measurement epochs, with the
//! estimate, status and judgement the FMUs expose.

use super::truth_sensors::truth_draw;
use super::*;

/// A filter estimate at one epoch.
#[derive(Debug, Clone, PartialEq)]
pub struct NavEstimate {
    /// Epoch time of the estimate \[s\] (0 before the first epoch).
    pub t: f64,
    /// Estimate x̂ (filter-model coordinates; N entries).
    pub x: Vec<f64>,
    /// 1σ per state (√P_ii).
    pub sigma: Vec<f64>,
    /// Covariance, row-major N×N.
    pub p: Vec<f64>,
    /// Filter's density estimate at its estimate, when it estimates density [kg/m³].
    pub density: Option<f64>,
    /// What the last update reported (default before the first epoch).
    pub info: StepInfo,
}

/// The estimate judged against the truth at its epoch.
#[derive(Debug, Clone, PartialEq)]
pub struct Judgement {
    /// Truth in filter coordinates (NaN where a state has no truth counterpart).
    pub truth: Vec<f64>,
    /// Estimation error x̂ − x (angles wrapped).
    pub err: Vec<f64>,
    /// NEES eᵀP⁻¹e over the states with a truth value, and its degrees of freedom.
    pub nees: Option<(f64, usize)>,
    /// True density at the epoch [kg/m³].
    pub density_true: f64,
}

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
        reason: String,
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

/// Object-safe view of a `NavFilter<N>` for N in 6..=10.
pub(super) trait DynFilter: Send {
    fn set_bank_angle(&mut self, bank: f64);
    fn step(
        &mut self,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
    ) -> Result<StepInfo, String>;
    fn estimate(&self, t: f64, info: StepInfo) -> NavEstimate;
    fn judge(&self, scenario: &Scenario, draw: &TruthDraw, sample: &TruthSample) -> Judgement;
}

pub(super) struct Dim<const N: usize>(Box<dyn NavFilter<N>>);

impl<const N: usize> DynFilter for Dim<N> {
    fn set_bank_angle(&mut self, bank: f64) {
        self.0.set_bank_angle(bank);
    }

    fn step(
        &mut self,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
    ) -> Result<StepInfo, String> {
        let info = self
            .0
            .predict(epoch.t)
            .and_then(|_| self.0.update(epoch, beacons))
            .map_err(|e| e.to_string())?;
        let (x, p) = self.0.estimate();
        if x.iter().chain(p.iter()).any(|v| !v.is_finite()) {
            return Err("estimate or covariance became non-finite".into());
        }
        Ok(info)
    }

    fn estimate(&self, t: f64, info: StepInfo) -> NavEstimate {
        let (x, p) = self.0.estimate();
        NavEstimate {
            t,
            x: x.iter().copied().collect(),
            sigma: (0..N).map(|i| p[(i, i)].max(0.0).sqrt()).collect(),
            p: (0..N)
                .flat_map(|i| (0..N).map(move |j| (i, j)))
                .map(|(i, j)| p[(i, j)])
                .collect(),
            density: self.0.density_estimate(),
            info,
        }
    }

    fn judge(&self, scenario: &Scenario, draw: &TruthDraw, sample: &TruthSample) -> Judgement {
        let (x, p) = self.0.estimate();
        let truth = truth_in_filter_coords::<N>(scenario, draw, sample);
        let err = estimation_error(scenario, &x, &truth);
        let step = NavStep {
            t: sample.t,
            x,
            p,
            truth,
            err,
            info: StepInfo::default(),
            density_est: None,
            density_profile_est: None,
            density_true: sample.density,
            truth_spherical: sample.spherical,
        };
        Judgement {
            truth: truth.iter().copied().collect(),
            err: err.iter().copied().collect(),
            nees: step.nees(),
            density_true: sample.density,
        }
    }
}

pub(super) fn make_filter<const N: usize>(
    kind: FilterKind,
    scenario: &Arc<Scenario>,
    draw: &TruthDraw,
    t0: &TruthSample,
    rng: &mut ChaCha8Rng,
) -> Result<Box<dyn DynFilter>, CoSimError> {
    let start = filter_start::<N>(scenario, draw, t0, rng);
    Ok(Box::new(Dim::<N>(build_filter::<N>(
        kind, scenario, &start,
    )?)))
}

/// A navigation filter alone, fed with measurement epochs.
pub struct NavigationCoSim {
    scenario: Arc<Scenario>,
    kind: FilterKind,
    pub(super) filter: Box<dyn DynFilter>,
    estimate: NavEstimate,
    pub(super) status: NavStatus,
    pub(super) time: f64,
    last_epoch_t: f64,
}

impl std::fmt::Debug for NavigationCoSim {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("NavigationCoSim")
            .field("scenario", &self.scenario.config.name)
            .field("kind", &self.kind)
            .field("time", &self.time)
            .field("status", &self.status)
            .finish()
    }
}

impl NavigationCoSim {
    /// Filter `kind` on `scenario`, started as the combined engine starts it for `seed` and
    /// `dispersed` (the scenario's `filter.initial`, or with `filter.sample_initial_from_p0` a draw
    /// around the seed's truth realisation at t = 0 from the seed's stream 1).
    pub fn new(
        scenario: Arc<Scenario>,
        kind: FilterKind,
        seed: u64,
        dispersed: bool,
    ) -> Result<NavigationCoSim, CoSimError> {
        let (draw, _) = truth_draw(&scenario, seed, dispersed);
        let t0 = truth_sample(&scenario, &draw, 0.0, &draw.initial, scenario.truth_bank);
        Self::with_truth(scenario, kind, seed, &draw, &t0)
    }

    pub(super) fn with_truth(
        scenario: Arc<Scenario>,
        kind: FilterKind,
        seed: u64,
        draw: &TruthDraw,
        t0: &TruthSample,
    ) -> Result<NavigationCoSim, CoSimError> {
        kind.check_fits(&scenario)?;
        let mut rng = ChaCha8Rng::seed_from_u64(seed);
        rng.set_stream(1);
        let filter = match scenario.filter_model.state_dim() {
            6 => make_filter::<6>(kind, &scenario, draw, t0, &mut rng)?,
            7 => make_filter::<7>(kind, &scenario, draw, t0, &mut rng)?,
            8 => make_filter::<8>(kind, &scenario, draw, t0, &mut rng)?,
            9 => make_filter::<9>(kind, &scenario, draw, t0, &mut rng)?,
            10 => make_filter::<10>(kind, &scenario, draw, t0, &mut rng)?,
            other => return Err(NavError::Dimension(other).into()),
        };
        let estimate = filter.estimate(0.0, StepInfo::default());
        Ok(NavigationCoSim {
            scenario,
            kind,
            filter,
            estimate,
            status: NavStatus::Initial,
            time: 0.0,
            last_epoch_t: 0.0,
        })
    }

    /// The scenario.
    pub fn scenario(&self) -> &Arc<Scenario> {
        &self.scenario
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
    /// starts with the scenario's `truth.bank_deg`).
    pub fn set_bank_angle(&mut self, bank: f64) -> Result<(), CoSimError> {
        if !bank.is_finite() {
            return Err(CoSimError::NonFiniteInput("bank angle"));
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
        let beacons = self.scenario.beacon_states(epoch.t);
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
    ) -> Result<StepReport, CoSimError> {
        check_step(self.time, t, h)?;
        if !bank.is_finite() {
            return Err(CoSimError::NonFiniteInput("bank angle"));
        }
        let mut report = StepReport::default();
        if let Some(e) = epoch
            && e.values.iter().flatten().any(|v| !v.is_finite())
        {
            return Err(CoSimError::NonFiniteInput("measurement"));
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

    pub(super) fn judge(&self, draw: &TruthDraw, sample: &TruthSample) -> Judgement {
        self.filter.judge(&self.scenario, draw, sample)
    }
}
