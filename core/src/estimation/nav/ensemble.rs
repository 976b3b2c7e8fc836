//! What the filters made of several EKFs share (the model bank's members, the fusion's local
//! filters): the members, a member dropped when it fails numerically, the combined estimate, its
//! time and the bank command every member flies.

use super::ekf_nav::EkfNav;
use super::nav_filter::FilterCore;
use super::nav_filter::NavFilter;
use crate::estimation::error::EstimationError;
use crate::estimation::onboard::Onboard;
use nalgebra::{SMatrix, SVector};
use std::sync::Arc;

/// Several EKFs and their combined estimate; the [`FilterCore`] of [`super::BankNav`] and
/// [`super::FusionNav`].
#[derive(Debug, Clone)]
pub(crate) struct EkfEnsemble<const N: usize> {
    /// The members; `None` once a member has failed numerically.
    pub(crate) members: Vec<Option<EkfNav<N>>>,
    /// The combined estimate and covariance.
    pub(crate) fused: (SVector<f64, N>, SMatrix<f64, N, N>),
    /// Time of the estimate \[s\].
    pub(crate) t: f64,
    /// Bank-angle command of the members' onboard models \[rad\].
    bank: f64,
    pub(crate) onboard: Arc<Onboard>,
}

impl<const N: usize> EkfEnsemble<N> {
    /// `members` on `onboard`, combined estimate `fused` at time 0.
    pub(crate) fn new(
        onboard: &Arc<Onboard>,
        members: Vec<EkfNav<N>>,
        fused: (SVector<f64, N>, SMatrix<f64, N, N>),
    ) -> Self {
        EkfEnsemble {
            members: members.into_iter().map(Some).collect(),
            fused,
            t: 0.0,
            bank: onboard.initial_bank,
            onboard: Arc::clone(onboard),
        }
    }

    /// Every live member predicts to `t_to` on its own; one that fails is dropped.
    pub(crate) fn predict_each(&mut self, t_to: f64) {
        for slot in self.members.iter_mut() {
            if let Some(f) = slot
                && f.predict(t_to).is_err()
            {
                *slot = None;
            }
        }
        self.t = t_to;
    }

    /// The first live member.
    pub(crate) fn first(&self) -> Option<&EkfNav<N>> {
        self.members.iter().flatten().next()
    }

    /// `Ok` while a member lives, else [`EkfEnsemble::all_failed`].
    pub(crate) fn alive(&self, what: &str) -> Result<(), EstimationError> {
        match self.first() {
            Some(_) => Ok(()),
            None => Err(Self::all_failed(what)),
        }
    }

    /// The error once every member (a `what`, e.g. `local filter`) has failed.
    pub(crate) fn all_failed(what: &str) -> EstimationError {
        EstimationError::NotPositiveDefinite {
            what: format!("every {what}'s covariance"),
        }
    }
}

impl<const N: usize> FilterCore<N> for EkfEnsemble<N> {
    fn state(&self) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
        self.fused
    }

    fn t(&self) -> f64 {
        self.t
    }

    fn bank(&self) -> f64 {
        self.bank
    }

    /// Every member (the combination itself has no dynamics or measurement model).
    fn set_bank(&mut self, bank_rad: f64) {
        for f in self.members.iter_mut().flatten() {
            f.set_bank_angle(bank_rad);
        }
        self.bank = bank_rad;
    }

    fn altitude(&self) -> f64 {
        self.onboard.model.altitude(&self.fused.0)
    }
}
