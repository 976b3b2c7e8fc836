//! Construct a navigation filter by kind.

use super::bank::BankNav;
use super::ekf_nav::EkfNav;
use super::fusion::FusionNav;
use super::setup::FilterStart;
use super::ukf_nav::UkfNav;
use super::{FilterKind, NavFilter};
use crate::estimation::EstimationError;
use crate::scenario::Scenario;
use std::sync::Arc;

/// Build filter `kind` on `scenario` from `start`.
pub fn build_filter<const N: usize>(
    kind: FilterKind,
    scenario: &Arc<Scenario>,
    start: &FilterStart<N>,
) -> Result<Box<dyn NavFilter<N>>, EstimationError> {
    Ok(match kind {
        FilterKind::Ekf => Box::new(EkfNav::new(scenario, start, None, 1.0)?),
        FilterKind::Ukf => Box::new(UkfNav::new(scenario, start)?),
        FilterKind::Ci => Box::new(FusionNav::new(scenario, start, false)?),
        FilterKind::Dcifaif => Box::new(FusionNav::new(scenario, start, true)?),
        FilterKind::Mmae => Box::new(BankNav::new(scenario, start, false)?),
        FilterKind::MmaeMoe => Box::new(BankNav::new(scenario, start, true)?),
    })
}
