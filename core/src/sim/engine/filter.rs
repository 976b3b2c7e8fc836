//! The engine's filter slot: a navigation filter of any supported state dimension behind one
//! object-safe interface, built through the one dimension switch
//! ([`crate::state_dim::with_state_dim`]). Every numerical result (estimate, σ, NEES, errors)
//! is computed in the filter's own fixed-size types and only then copied out.

use super::judge;
use super::truth::TruthSample;
use crate::estimation::nav::{FilterKind, FilterStart, NavFilter, StepInfo, build_filter};
use crate::estimation::{EstimationError, Onboard};
use crate::math::V3;
use crate::math::all_finite;
use crate::scenario::{Scenario, TruthDraw};
use crate::sensors::MeasurementEpoch;
use crate::state_dim::{DimVisitor, UnsupportedDimension, with_state_dim};
use nalgebra::SVector;
use std::sync::Arc;
use thiserror::Error;

/// Why a filter stopped processing epochs (its run reports it; nothing panics).
#[derive(Debug, Error, Clone, PartialEq)]
pub enum FilterFailure {
    /// A numerical failure the filter reported (non-positive-definite covariance, …).
    #[error(transparent)]
    Estimation(#[from] EstimationError),
    /// The estimate or its covariance holds NaN or ∞ after a step.
    #[error("estimate or covariance became non-finite")]
    NonFiniteEstimate,
}

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
    /// NEES over the six kinematic states (dof 6).
    pub nees_kinematic: Option<f64>,
    /// True density at the epoch [kg/m³].
    pub density_true: f64,
    /// Position error norm \[m\] and velocity error norm [m/s].
    pub pos_vel_err: (f64, f64),
    /// Downrange and crossrange position error \[m\] (along / across the true heading).
    pub downrange_crossrange: (f64, f64),
    /// Radial ("up") position error \[m\]: estimated minus true planet-centred radius.
    pub up_m: f64,
    /// (ρ̂(h) − ρ(h))/ρ(h) of the filter's density profile at the true altitude h (seed 001
    /// eq. 70), for filters that estimate density.
    pub density_profile_rel_err: Option<f64>,
    /// (ρ̂(x̂) − ρ(x))/ρ(x) of the filter's density at its own estimate.
    pub density_at_estimate_rel_err: Option<f64>,
}

/// Object-safe view of a `NavFilter<N>` for every supported N.
pub(crate) trait ErasedFilter: Send {
    fn set_bank_angle(&mut self, bank: f64);
    /// The bank the onboard models currently fly \[rad\].
    fn bank_angle(&self) -> f64;
    /// Time of the estimate \[s\].
    fn time(&self) -> f64;
    /// Propagate to `t` (no update), checking the result is finite.
    fn predict_to(&mut self, t: f64) -> Result<(), FilterFailure>;
    fn step(
        &mut self,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
    ) -> Result<StepInfo, FilterFailure>;
    fn estimate(&self, t: f64, info: StepInfo) -> NavEstimate;
    fn judge(&self, scenario: &Scenario, draw: &TruthDraw, sample: &TruthSample) -> Judgement;
}

struct Dim<const N: usize>(Box<dyn NavFilter<N>>);

impl<const N: usize> ErasedFilter for Dim<N> {
    fn set_bank_angle(&mut self, bank: f64) {
        self.0.set_bank_angle(bank);
    }

    fn bank_angle(&self) -> f64 {
        self.0.bank_angle()
    }

    fn time(&self) -> f64 {
        self.0.time()
    }

    fn predict_to(&mut self, t: f64) -> Result<(), FilterFailure> {
        self.0.predict(t)?;
        let (x, p) = self.0.estimate();
        if !(all_finite(x.as_slice()) && all_finite(p.as_slice())) {
            return Err(FilterFailure::NonFiniteEstimate);
        }
        Ok(())
    }

    fn step(
        &mut self,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
    ) -> Result<StepInfo, FilterFailure> {
        self.0.predict(epoch.t)?;
        let info = self.0.update(epoch, beacons)?;
        let (x, p) = self.0.estimate();
        if !(all_finite(x.as_slice()) && all_finite(p.as_slice())) {
            return Err(FilterFailure::NonFiniteEstimate);
        }
        Ok(info)
    }

    fn estimate(&self, t: f64, info: StepInfo) -> NavEstimate {
        let (x, p) = self.0.estimate();
        NavEstimate {
            t,
            x: x.as_slice().to_vec(),
            sigma: (0..N).map(|i| p[(i, i)].max(0.0).sqrt()).collect(),
            // Row-major: Pᵀ's column-major storage.
            p: p.transpose().as_slice().to_vec(),
            density: self.0.density_estimate(),
            info,
        }
    }

    fn judge(&self, scenario: &Scenario, draw: &TruthDraw, sample: &TruthSample) -> Judgement {
        let (x, p) = self.0.estimate();
        let truth = SVector::<f64, N>::from_column_slice(&judge::truth_in_filter_coords(
            scenario, draw, sample, N,
        ));
        let err = judge::estimation_error(scenario, &x, &truth);
        let rho = sample.density;
        let rel = |d: f64| (d - rho) / rho;
        Judgement {
            truth: truth.as_slice().to_vec(),
            err: err.as_slice().to_vec(),
            nees: judge::nees(&err, &p, &truth),
            nees_kinematic: judge::nees_kinematic(&err, &p),
            density_true: rho,
            pos_vel_err: judge::pos_vel_error(scenario, &x, &truth, &err),
            downrange_crossrange: judge::downrange_crossrange(
                scenario,
                &x,
                sample.t,
                &sample.spherical,
            ),
            up_m: judge::estimate_spherical(scenario, &x, sample.t)[0] - sample.spherical[0],
            density_profile_rel_err: self.0.density_profile(sample.altitude).map(rel),
            density_at_estimate_rel_err: self.0.density_estimate().map(rel),
        }
    }
}

/// Why the engine could not build a filter.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum BuildError {
    /// The onboard state dimension has no compiled filter.
    #[error(transparent)]
    Dimension(#[from] UnsupportedDimension),
    /// The filter refused its start or tuning.
    #[error("cannot build the filter: {0}")]
    Filter(#[from] EstimationError),
}

struct Build<'a> {
    kind: FilterKind,
    onboard: &'a Arc<Onboard>,
    x0: &'a [f64],
}

impl DimVisitor for Build<'_> {
    type Output = Result<Box<dyn ErasedFilter>, EstimationError>;

    fn visit<const N: usize, const L: usize>(self) -> Self::Output {
        let start = FilterStart::<N>::with_estimate(self.onboard, self.x0);
        let filter = build_filter::<N, L>(self.kind, self.onboard, &start)?;
        Ok(Box::new(Dim::<N>(filter)))
    }
}

/// Filter `kind` on `onboard` started at the initial estimate `x0` (P0 and Q from the tuning).
pub(crate) fn build_erased(
    kind: FilterKind,
    onboard: &Arc<Onboard>,
    x0: &[f64],
) -> Result<Box<dyn ErasedFilter>, BuildError> {
    let visitor = Build { kind, onboard, x0 };
    Ok(with_state_dim(onboard.state_dim(), visitor)??)
}
