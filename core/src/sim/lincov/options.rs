//! What a LinCov can analyse ([`unsupported_reason`]) and what it carries beyond the
//! first-order recursion ([`LinCovOptions`]).

use crate::estimation::nav::FilterKind;

/// Why LinCov cannot analyse filter `kind` (`None`: it can).
pub fn unsupported_reason(kind: FilterKind) -> Option<&'static str> {
    Some(match kind {
        FilterKind::Ekf | FilterKind::Ukf | FilterKind::Ci | FilterKind::Dcifaif => return None,
        FilterKind::Mmae | FilterKind::MmaeMoe => {
            "its model probabilities depend on the measured innovations, so its gain is not \
             linear in the measurements"
        }
        FilterKind::UkfCm => "it adapts its process noise Q from the measured innovations",
        FilterKind::UkfAc => "it adapts a density correction factor from the measured innovations",
        FilterKind::UskfNn => "it trains its density network online on the measurements",
    })
}

/// What a LinCov carries beyond the first-order recursion.
#[derive(Debug, Clone, Copy, Default, PartialEq, Eq)]
pub struct LinCovOptions {
    /// Carry the second-order mean: every filter's time update gains ½ Σ ∂²F/∂x_a∂x_b
    /// (E\[δx̂δx̂ᵀ\] − E\[δxδxᵀ\])_ab and, for a single (non-iterated) update, each measurement
    /// the same term of h (`second_order.rs`): the bias a filter's curved model gives a large
    /// error (a CI local's drag at a km-sized altitude error). 2N more time updates and
    /// measurement linearisations per epoch. Off by default: the first-order LinCov is the one
    /// validated on every built-in; docs/results.md measures both.
    pub second_order_mean: bool,
}
