//! Pieces the navigation filters share (mostly the UKF family): the prediction sub-steps, the
//! epoch's measurement vector with its noise, the measurement function over sigma points, the step
//! report, and [`UkfCore`], the state and loops of every UKF navigation filter.

use super::nav_filter::FilterCore;
use super::step_info::StepInfo;
use crate::atmosphere::Atmosphere;
use crate::dynamics::EntryModel;
use crate::estimation::error::EstimationError;
use crate::estimation::onboard::Onboard;
use crate::estimation::process_noise::ProcessNoiseModel;
use crate::estimation::ukf::{Ukf, UkfUpdate, UkfWorkspace};
use crate::math::V3;
use crate::sensors::MeasurementEpoch;
use crate::sensors::channels::kinematics;
use nalgebra::{DMatrix, DVector, SMatrix, SVector};
use std::sync::Arc;

/// Most RK4 sub-steps one prediction may take (about 0.2 s of EKF work; 28 h at a 1 s filter
/// step). A longer prediction is refused with an error instead of running (or allocating) for an
/// unbounded time: an FMI master can ask for any step size.
pub const MAX_PREDICTION_SUBSTEPS: usize = 100_000;

/// Number and length of the RK4 sub-steps that cover `dt` with steps no longer than `step`; an
/// error past [`MAX_PREDICTION_SUBSTEPS`] or for a non-finite `dt`.
pub(crate) fn substeps(dt: f64, step: f64) -> Result<(usize, f64), EstimationError> {
    let n = ((dt / step) - 1e-9).ceil().max(1.0);
    if !(n.is_finite() && n <= MAX_PREDICTION_SUBSTEPS as f64) {
        return Err(EstimationError::InvalidInput(format!(
            "a prediction over {dt} s needs {n} sub-steps of at most {step} s; the limit is {MAX_PREDICTION_SUBSTEPS}"
        )));
    }
    let n = n as usize;
    Ok((n, dt / n as f64))
}

/// The channels available at `epoch` (indices into `onboard.channels`), their values z and the
/// diagonal noise covariance R the filters assume; `None` when nothing was measured.
pub(crate) fn epoch_measurements(
    onboard: &Onboard,
    epoch: &MeasurementEpoch,
) -> Option<(Vec<usize>, DVector<f64>, DMatrix<f64>)> {
    let slots: Vec<usize> = epoch
        .values
        .iter()
        .enumerate()
        .filter_map(|(c, v)| v.map(|_| c))
        .collect();
    if slots.is_empty() {
        return None;
    }
    let z = DVector::from_iterator(
        slots.len(),
        slots.iter().map(|&c| epoch.values[c].unwrap_or(0.0)),
    );
    let r = DMatrix::from_diagonal(&DVector::from_iterator(
        slots.len(),
        slots
            .iter()
            .enumerate()
            .map(|(i, &c)| onboard.channels[c].noise.sigma(z[i]).powi(2)),
    ));
    Some((slots, z, r))
}

/// The predicted measurements h(x) of the channels `slots` at epoch time `t` with bank-angle
/// command `bank` \[rad\], written to `out` (one entry per slot): the UKF's measurement function,
/// evaluated at each sigma point.
#[allow(clippy::too_many_arguments)]
pub(crate) fn predict_channels<A: Atmosphere, const L: usize>(
    onboard: &Onboard,
    model: &EntryModel<A>,
    x: &SVector<f64, L>,
    t: f64,
    bank: f64,
    beacons: &[(V3<f64>, V3<f64>)],
    slots: &[usize],
    out: &mut [f64],
) {
    let kin = kinematics(model, x, t);
    let mut triad = None;
    for (o, &c) in out.iter_mut().zip(slots) {
        *o = onboard.measurement.evaluate_sharing_triad(
            model,
            x,
            &kin,
            bank,
            beacons,
            onboard.channels[c].channel,
            &mut triad,
        );
    }
}

/// What a UKF update of the channels `slots` reports (per channel the marginal ν_i²/S_ii).
pub(crate) fn step_info(upd: &UkfUpdate, slots: &[usize]) -> StepInfo {
    StepInfo {
        nis: Some(upd.nis),
        n_meas: slots.len(),
        innovations: upd.innovation.iter().copied().collect(),
        weights: None,
        nis_terms: slots
            .iter()
            .enumerate()
            .map(|(i, &c)| (c, upd.innovation[i] * upd.innovation[i] / upd.s[(i, i)]))
            .collect(),
        gate: None,
    }
}

/// The state every UKF navigation filter carries (onboard knowledge, onboard model, UKF and its
/// workspace, time, bank command) and the predict / update loops they share. The filters add
/// what makes each one different: covariance matching (`ukf-cm`), the augmented correction
/// factor (`ukf-ac`), the consider parameter and the network adaptation (`uskf-nn`).
#[derive(Debug, Clone)]
pub(crate) struct UkfCore<A, const L: usize> {
    pub(crate) onboard: Arc<Onboard>,
    pub(crate) model: EntryModel<A>,
    pub(crate) ukf: Ukf<L>,
    pub(crate) ws: UkfWorkspace<L>,
    pub(crate) t: f64,
    /// Bank-angle command of the onboard models \[rad\] (starts at the onboard initial bank).
    pub(crate) bank: f64,
    /// `Some(i)`: state i scales the onboard density (𝒦 of UKF-AC, c of USKF-NN) at every sigma
    /// point, through the model's density factor.
    density_state: Option<usize>,
}

impl<A: Atmosphere, const L: usize> UkfCore<A, L> {
    /// A core on `onboard` with dynamics `model` and filter `ukf`.
    pub(crate) fn new(
        onboard: &Arc<Onboard>,
        model: EntryModel<A>,
        ukf: Ukf<L>,
        density_state: Option<usize>,
    ) -> Self {
        UkfCore {
            onboard: Arc::clone(onboard),
            model,
            ukf,
            ws: UkfWorkspace::default(),
            t: 0.0,
            bank: onboard.initial_bank,
            density_state,
        }
    }

    /// The sub-steps `(n, h)` from the filter time to `t_to` and the onboard filter step;
    /// `None` when `t_to` is not later than the filter time.
    pub(crate) fn substeps_to(
        &self,
        t_to: f64,
    ) -> Result<Option<(usize, f64, f64)>, EstimationError> {
        let dt = t_to - self.t;
        if dt <= 0.0 {
            return Ok(None);
        }
        let step = self.onboard.filter_step_s;
        let (n, h) = substeps(dt, step)?;
        Ok(Some((n, h, step)))
    }

    /// Predict to `t_to` with process noise `q` per filter step (scaled to each sub-step), every
    /// state moved by the model's RK4 step only; the noise added in total, `None` when `t_to` is
    /// not later than the filter time.
    pub(crate) fn predict(
        &mut self,
        t_to: f64,
        q: &SMatrix<f64, L, L>,
    ) -> Result<Option<SMatrix<f64, L, L>>, EstimationError> {
        let Some((n, h, step)) = self.substeps_to(t_to)? else {
            return Ok(None);
        };
        let q = q * (h / step);
        self.propagate(t_to, n, h, &q, |_, _| {}).map(Some)
    }

    /// `n` UKF time updates of length `h` with process noise `q` each plus the process-noise
    /// model's state-dependent part at the mean (the truth's RK4 step per sigma point, the
    /// density scaled by the density state if any; `post(x, y)` may then change the propagated
    /// point y of x), ending at `t_to`. Returns the noise added in total.
    pub(crate) fn propagate(
        &mut self,
        t_to: f64,
        n: usize,
        h: f64,
        q: &SMatrix<f64, L, L>,
        post: impl Fn(&SVector<f64, L>, &mut SVector<f64, L>),
    ) -> Result<SMatrix<f64, L, L>, EstimationError> {
        let (bank, density_state) = (self.bank, self.density_state);
        let noise_model = self.onboard.tuning.process_noise;
        let model = &mut self.model;
        // The state-dependent part added over the sub-steps (zero for the constant model).
        let mut added = SMatrix::<f64, L, L>::zeros();
        for _ in 0..n {
            let q_k = match noise_model {
                ProcessNoiseModel::Constant => *q,
                ProcessNoiseModel::AeroScaled(a) => {
                    let mean = self.ukf.x;
                    if let Some(i) = density_state {
                        model.density_factor = mean[i];
                    }
                    let phi = model.linear_stm(&mean, bank, h);
                    let extra = a.over_substep(model, &mean, bank, h, &phi);
                    added += extra;
                    q + extra
                }
            };
            self.ukf.predict_with(
                &mut self.ws,
                |x| {
                    if let Some(i) = density_state {
                        model.density_factor = x[i];
                    }
                    let mut y = model.step(x, bank, h);
                    post(x, &mut y);
                    y
                },
                &q_k,
            )?;
        }
        self.t = t_to;
        Ok(q * n as f64 + added)
    }

    /// UKF measurement update with the channels `slots` (values `z`, noise `r`) of the epoch at
    /// `t`.
    pub(crate) fn update_measured(
        &mut self,
        slots: &[usize],
        z: &DVector<f64>,
        r: &DMatrix<f64>,
        t: f64,
        beacons: &[(V3<f64>, V3<f64>)],
    ) -> Result<StepInfo, EstimationError> {
        let (sc, bank, density_state) = (&*self.onboard, self.bank, self.density_state);
        let model = &mut self.model;
        let h = |x: &SVector<f64, L>, out: &mut [f64]| {
            if let Some(i) = density_state {
                model.density_factor = x[i];
            }
            predict_channels(sc, model, x, t, bank, beacons, slots, out);
            Ok(())
        };
        let upd = self.ukf.update_with(&mut self.ws, h, z, r)?;
        Ok(step_info(&upd, slots))
    }

    /// UKF measurement update with every available channel of `epoch` (nothing when none is).
    pub(crate) fn update(
        &mut self,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
    ) -> Result<StepInfo, EstimationError> {
        match epoch_measurements(&self.onboard, epoch) {
            Some((slots, z, r)) => self.update_measured(&slots, &z, &r, epoch.t, beacons),
            None => Ok(StepInfo::default()),
        }
    }
}

/// The navigation states are the first `N` of the `L` (an augmented filter carries one more).
impl<A: Atmosphere, const L: usize, const N: usize> FilterCore<N> for UkfCore<A, L> {
    fn state(&self) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
        (
            self.ukf.x.fixed_rows::<N>(0).into_owned(),
            self.ukf.p.fixed_view::<N, N>(0, 0).into_owned(),
        )
    }

    fn t(&self) -> f64 {
        self.t
    }

    fn bank(&self) -> f64 {
        self.bank
    }

    fn set_bank(&mut self, bank_rad: f64) {
        self.bank = bank_rad;
    }

    fn altitude(&self) -> f64 {
        self.model.altitude(&self.ukf.x)
    }
}
