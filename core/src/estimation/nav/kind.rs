//! The navigation filters by name ([`FilterKind`]) and why one cannot be used ([`NavError`]);
//! whether a filter fits a scenario's onboard view is in [`super::fit`].

use crate::state_dim::UnsupportedDimension;
use thiserror::Error;

/// Why a filter cannot be used as asked.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum NavError {
    /// Unknown filter name.
    #[error("unknown filter '{name}'; valid filters are: {valid}")]
    UnknownFilter {
        /// What was asked for.
        name: String,
        /// Comma-separated valid names.
        valid: String,
    },
    /// The filter needs something the scenario does not have.
    #[error(
        "filter '{filter}' does not fit scenario '{scenario}': {reason}; filters that fit: {fits}"
    )]
    DoesNotFit {
        /// Filter name.
        filter: String,
        /// Scenario name.
        scenario: String,
        /// What is missing.
        reason: String,
        /// Filters that do fit this scenario.
        fits: String,
    },
    /// The filter state dimension is not supported.
    #[error(transparent)]
    Dimension(#[from] UnsupportedDimension),
}

/// The navigation filters available to trade studies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum FilterKind {
    /// Centralised EKF over every channel (seed 000 eq. 17–18).
    Ekf,
    /// Centralised UKF (seed 001 eq. 41–66 without consider states).
    Ukf,
    /// One local EKF per beacon (IMU + that beacon), fused by covariance intersection with
    /// determinant-optimal weights, without feedback (seed 000 §3.3).
    Ci,
    /// Distributed CI fusion with information feedback and fast ∞-norm weights (seed 000 §3.4).
    Dcifaif,
    /// Classical multiple-model bank over density biases (Magill posterior probabilities).
    Mmae,
    /// Seed 003's modified mixture-of-experts bank with measurement normalisation (eq. 17–25).
    MmaeMoe,
    /// UKF with Myers–Tapley process-noise covariance matching (seed 001 eq. 20–21, batch 10).
    UkfCm,
    /// UKF with an augmented density correction factor 𝒦 (seed 001 eq. 24–26, random walk).
    UkfAc,
    /// Unscented Schmidt–Kalman filter with an online-adapted density network (seed 001 §IV).
    UskfNn,
}

impl FilterKind {
    /// All filters, in listing order.
    pub const ALL: [FilterKind; 9] = [
        FilterKind::Ekf,
        FilterKind::Ukf,
        FilterKind::Ci,
        FilterKind::Dcifaif,
        FilterKind::Mmae,
        FilterKind::MmaeMoe,
        FilterKind::UkfCm,
        FilterKind::UkfAc,
        FilterKind::UskfNn,
    ];

    /// The name used on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            FilterKind::Ekf => "ekf",
            FilterKind::Ukf => "ukf",
            FilterKind::Ci => "ci",
            FilterKind::Dcifaif => "dcifaif",
            FilterKind::Mmae => "mmae",
            FilterKind::MmaeMoe => "mmae-moe",
            FilterKind::UkfCm => "ukf-cm",
            FilterKind::UkfAc => "ukf-ac",
            FilterKind::UskfNn => "uskf-nn",
        }
    }

    /// Parse a filter name (the one parser of filter names; [`FromStr`](std::str::FromStr) calls it).
    pub fn parse(name: &str) -> Result<FilterKind, NavError> {
        FilterKind::ALL
            .into_iter()
            .find(|k| k.name() == name.trim())
            .ok_or_else(|| NavError::UnknownFilter {
                name: name.to_string(),
                valid: FilterKind::ALL.map(|k| k.name()).join(", "),
            })
    }
}

impl std::str::FromStr for FilterKind {
    type Err = NavError;

    fn from_str(name: &str) -> Result<FilterKind, NavError> {
        FilterKind::parse(name)
    }
}

impl std::fmt::Display for FilterKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}
