//! The traits every navigation filter implements: [`NavFilter`] (predict, update, what it
//! reports), the shared state it reads through [`FilterCore`], and [`NavFilterClone`].

use super::step_info::StepInfo;
use crate::estimation::error::EstimationError;
use crate::math::V3;
use crate::sensors::MeasurementEpoch;
use nalgebra::{SMatrix, SVector};

/// Cloning a boxed filter (FMU state snapshots, benchmarks). Implemented for every `Clone` filter.
pub trait NavFilterClone<const N: usize> {
    /// A boxed copy of this filter, state included.
    fn clone_box(&self) -> Box<dyn NavFilter<N>>;
}

impl<T: NavFilter<N> + Clone + 'static, const N: usize> NavFilterClone<N> for T {
    fn clone_box(&self) -> Box<dyn NavFilter<N>> {
        Box::new(self.clone())
    }
}

/// The state every navigation filter keeps besides its algorithm: the estimate it reports, its
/// time and the bank command its onboard models fly. One implementation serves a family of
/// filters (`UkfCore` the UKFs, `EkfEnsemble` the bank and the fusion); [`NavFilter`]'s provided
/// methods read it through [`NavFilter::core`], so each filter writes only what differs.
pub trait FilterCore<const N: usize> {
    /// Current estimate and covariance of the `N` navigation states.
    fn state(&self) -> (SVector<f64, N>, SMatrix<f64, N, N>);
    /// Current time of the estimate \[s\].
    fn t(&self) -> f64;
    /// The bank-angle command σ \[rad\] the onboard models use.
    fn bank(&self) -> f64;
    /// Set the bank-angle command σ \[rad\] of the onboard models.
    fn set_bank(&mut self, bank_rad: f64);
    /// Altitude of the current estimate \[m\].
    fn altitude(&self) -> f64;
}

/// A navigation filter over an `N`-dimensional state.
pub trait NavFilter<const N: usize>: Send + NavFilterClone<N> {
    /// Propagate the estimate from its current time to `t_to` \[s\].
    fn predict(&mut self, t_to: f64) -> Result<(), EstimationError>;
    /// Measurement update with the epoch's available channels; `beacons[i]` is the inertial
    /// (position, velocity) of beacon i at the epoch time.
    fn update(
        &mut self,
        epoch: &MeasurementEpoch,
        beacons: &[(V3<f64>, V3<f64>)],
    ) -> Result<StepInfo, EstimationError>;
    /// The shared state the provided methods below read.
    fn core(&self) -> &dyn FilterCore<N>;
    /// The shared state, to change the bank command ([`NavFilter::set_bank_angle`]).
    fn core_mut(&mut self) -> &mut dyn FilterCore<N>;
    /// Current estimate and covariance.
    fn estimate(&self) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
        self.core().state()
    }
    /// The estimate a measurement update at the current time would start from (after
    /// [`NavFilter::predict`]): the current estimate, except for filters of several members whose
    /// combined estimate is only formed at an update (fusion, banks), which combine their
    /// members' priors. The innovation gate ([`GatedNav`](super::gate::GatedNav)) tests measurements against it.
    fn prior(&self) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
        self.estimate()
    }
    /// The beacons the innovation gate has excluded ([`GatedNav`](super::gate::GatedNav)), told before each update.
    /// Their channels are already withheld from the epoch; a filter that has more to do about it
    /// overrides this (DCIFAIF: the excluded beacon's local filter leaves the fusion).
    fn exclude_beacons(&mut self, beacons: &[usize]) {
        let _ = beacons;
    }
    /// Current time of the estimate \[s\].
    fn time(&self) -> f64 {
        self.core().t()
    }
    /// Set the bank-angle command σ \[rad\] the filter's onboard dynamics and measurement models
    /// use from now on (held until the next call). Every filter starts with the onboard initial
    /// bank ([`Onboard::initial_bank`](crate::estimation::Onboard::initial_bank)); a guidance loop that commands another bank tells the filter here,
    /// since the command is known onboard. Setting the current value changes nothing.
    fn set_bank_angle(&mut self, bank_rad: f64) {
        self.core_mut().set_bank(bank_rad);
    }
    /// The bank-angle command σ \[rad\] the filter's onboard models currently use.
    fn bank_angle(&self) -> f64 {
        self.core().bank()
    }
    /// The filter's density estimate at its current estimate [kg/m³], for filters that estimate
    /// density (None otherwise): by default its density profile at the estimate's altitude.
    fn density_estimate(&self) -> Option<f64> {
        self.density_profile(self.core().altitude())
    }
    /// The filter's current density *profile* evaluated at `altitude_m` [kg/m³] (None for filters
    /// that do not estimate density). Seed 001 eq. 70 / Table 6 compare this, at the true altitude,
    /// with the true density: it measures the onboard model, not the altitude error.
    fn density_profile(&self, altitude_m: f64) -> Option<f64> {
        let _ = altitude_m;
        None
    }
}
