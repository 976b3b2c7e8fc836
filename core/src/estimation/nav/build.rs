//! Construct a navigation filter by kind.

use super::bank::BankNav;
use super::ekf_nav::EkfNav;
use super::fusion::FusionNav;
use super::setup::FilterStart;
use super::ukf_ac::UkfAcNav;
use super::ukf_cm::UkfCmNav;
use super::ukf_nav::UkfNav;
use super::uskf_nn::UskfNnNav;
use super::{FilterKind, NavFilter};
use crate::estimation::EstimationError;
use crate::scenario::Scenario;
use std::any::Any;
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
        FilterKind::UkfCm => Box::new(UkfCmNav::new(scenario, start)?),
        FilterKind::UkfAc => {
            eight_state(kind, start, |s8| Ok(Box::new(UkfAcNav::new(scenario, s8)?)))?
        }
        FilterKind::UskfNn => eight_state(kind, start, |s8| {
            Ok(Box::new(UskfNnNav::new(scenario, s8)?))
        })?,
    })
}

/// Build an 8-state-only filter (it carries a 9th internal state) for a generic `N`: succeeds
/// exactly when `N == 8`, by `Any` downcasts of the start and of the boxed filter.
fn eight_state<const N: usize>(
    kind: FilterKind,
    start: &FilterStart<N>,
    make: impl FnOnce(&FilterStart<8>) -> Result<Box<dyn NavFilter<8>>, EstimationError>,
) -> Result<Box<dyn NavFilter<N>>, EstimationError> {
    let wrong = || {
        EstimationError::InvalidInput(format!(
            "filter '{}' needs the 8-state model [r, lon, lat, v, fpa, heading, CdS/m, L/D]; this scenario's filter has {N} states",
            kind.name()
        ))
    };
    let s8 = (start as &dyn Any)
        .downcast_ref::<FilterStart<8>>()
        .ok_or_else(wrong)?;
    let b: Box<dyn NavFilter<8>> = make(s8)?;
    (Box::new(b) as Box<dyn Any>)
        .downcast::<Box<dyn NavFilter<N>>>()
        .map(|b| *b)
        .map_err(|_| wrong())
}
