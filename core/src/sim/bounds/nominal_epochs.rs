//! The beacon-independent part of the nominal bound, epoch by epoch ([`Epoch`]: the transition,
//! the information of the non-radio channels, the position map and the vehicle's position),
//! collected once along the nominal truth ([`Collect`]).

use super::nominal_bound_error::NominalBoundError;
use super::pcrlb::NoBound;
use super::pcrlb::TruthStates;
use super::pcrlb::bound_model;
use super::pcrlb::information;
use super::pcrlb::transition;
use super::pcrlb_epochs::KIN;
use crate::frames::spherical_to_position;
use crate::scenario::Scenario;
use crate::sim::engine::RecordedRun;
use crate::state_dim::DimVisitor;
use nalgebra::SMatrix;

/// One epoch's beacon-independent data (matrices column-major, N the filter dimension).
#[derive(Debug, Clone)]
pub(super) struct Epoch {
    pub(super) t: f64,
    pub(super) phi: Vec<f64>,
    /// Information of the non-radio channels (`None`: none measured).
    pub(super) base: Option<Vec<f64>>,
    /// 3×N position map.
    pub(super) jp: Vec<f64>,
    /// Vehicle planet-fixed position \[m\].
    pub(super) vehicle_fixed: [f64; 3],
    /// Rotation angle from the planet-fixed to the position map's frame (0 when the map is
    /// planet-fixed, ωt for inertial Cartesian states).
    pub(super) angle: f64,
    /// The range sensor samples at this epoch.
    pub(super) ranged: bool,
}

/// Collects the beacon-independent epochs (dimension N).
pub(super) struct Collect<'a> {
    pub(super) scenario: &'a Scenario,
    pub(super) rec: &'a RecordedRun,
}

impl DimVisitor for Collect<'_> {
    type Output = Result<Vec<Epoch>, NominalBoundError>;

    fn visit<const N: usize, const L: usize>(self) -> Self::Output {
        let (scenario, rec) = (self.scenario, self.rec);
        let model = bound_model(scenario, &rec.draw)?;
        let truth = TruthStates::<N>::new(scenario, rec)?;
        let first = rec.truth.samples.first().ok_or(NoBound::EmptyRun)?;
        let (mut t_prev, mut x_prev) = (first.t, truth.at(first));
        let omega = model.omega();
        let cartesian = model.kind.is_cartesian();
        let mut out = Vec::with_capacity(rec.truth.epochs.len());
        for (epoch, sample) in rec.truth.epochs_with_truth() {
            let phi = transition(scenario, &model, &x_prev, epoch.t - t_prev);
            let x = truth.checked_at(sample)?;
            let radio = |c: usize| scenario.channels[c].channel.beacon().is_some();
            let ranged = (0..epoch.values.len()).any(|c| radio(c) && epoch.values[c].is_some());
            let mut others = epoch.clone();
            for (c, v) in others.values.iter_mut().enumerate() {
                if radio(c) {
                    *v = None;
                }
            }
            let (base, (jp, _)) = information(scenario, &model, &x, &others, scenario.truth_bank)?;
            let mut jp_n = SMatrix::<f64, 3, N>::zeros();
            for i in 0..3 {
                for j in 0..N.min(KIN) {
                    jp_n[(i, j)] = jp[(i, j)];
                }
            }
            let [r, lon, lat] = [
                sample.spherical[0],
                sample.spherical[1],
                sample.spherical[2],
            ];
            out.push(Epoch {
                t: epoch.t,
                phi: phi.as_slice().to_vec(),
                base: (base.iter().any(|v| *v != 0.0)).then(|| base.as_slice().to_vec()),
                jp: jp_n.as_slice().to_vec(),
                vehicle_fixed: spherical_to_position(r, lon, lat),
                angle: if cartesian { omega * epoch.t } else { 0.0 },
                ranged,
            });
            (t_prev, x_prev) = (epoch.t, x);
        }
        Ok(out)
    }
}
