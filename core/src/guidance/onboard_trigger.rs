//! [`onboard_trigger`]: the deployment trigger function on the onboard view, for every trigger
//! (what the guidance FMU, which holds only the onboard view, deploys on).

use super::deploy::{DeployBox, OnboardDeploy};
use super::longitudinal::Trigger;
use super::nav_state::NavState;

/// The deployment trigger function on the onboard view at time `t`: the range trigger by
/// [`super::deploy::RangeTrigger::on_estimate`], the others by [`Trigger::function`] with the
/// estimated speed and `density`, the onboard density at the estimated altitude.
pub fn onboard_trigger(
    trigger: &Trigger,
    window: &DeployBox,
    nav: &NavState,
    t: f64,
    density: f64,
    onboard: &OnboardDeploy,
) -> f64 {
    match trigger {
        Trigger::Range(rt) => rt.on_estimate(window, nav, t, onboard),
        other => other.function(density, nav.speed()),
    }
}
