//! Construct a navigation filter by kind.

use super::bank::BankNav;
use super::ekf_nav::EkfNav;
use super::fusion::FusionNav;
use super::gate::GatedNav;
use super::kind::FilterKind;
use super::nav_filter::NavFilter;
use super::start::FilterStart;
use super::ukf_ac::UkfAcNav;
use super::ukf_cm::UkfCmNav;
use super::ukf_nav::UkfNav;
use super::uskf_nn::UskfNnNav;
use crate::estimation::error::EstimationError;
use crate::estimation::onboard::Onboard;
use std::sync::Arc;

/// Build filter `kind` on the `onboard` models from `start`. `L` must be `N + 1` (the internal
/// size of UKF-AC and USKF-NN); [`crate::state_dim::with_state_dim`] supplies both.
pub fn build_filter<const N: usize, const L: usize>(
    kind: FilterKind,
    onboard: &Arc<Onboard>,
    start: &FilterStart<N>,
) -> Result<Box<dyn NavFilter<N>>, EstimationError> {
    let states = onboard.state_dim();
    if N != states {
        return Err(EstimationError::InvalidInput(format!(
            "a {N}-state '{}' filter cannot run on the onboard model with {states} states",
            kind.name()
        )));
    }
    let filter: Box<dyn NavFilter<N>> = match kind {
        FilterKind::Ekf => Box::new(EkfNav::new(onboard, start, None, 1.0)?),
        FilterKind::Ukf => Box::new(UkfNav::new(onboard, start)?),
        FilterKind::Ci => Box::new(FusionNav::new(onboard, start, false)?),
        FilterKind::Dcifaif => Box::new(FusionNav::new(onboard, start, true)?),
        FilterKind::Mmae => Box::new(BankNav::new(onboard, start, false)?),
        FilterKind::MmaeMoe => Box::new(BankNav::new(onboard, start, true)?),
        FilterKind::UkfCm => Box::new(UkfCmNav::new(onboard, start)?),
        FilterKind::UkfAc => Box::new(UkfAcNav::<N, L>::new(onboard, start)?),
        FilterKind::UskfNn => Box::new(UskfNnNav::<N, L>::new(onboard, start)?),
    };
    Ok(match onboard.tuning.gating {
        Some(config) if config.enabled => Box::new(GatedNav::new(filter, onboard, config)),
        _ => filter,
    })
}
