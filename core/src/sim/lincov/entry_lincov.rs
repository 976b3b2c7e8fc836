//! [`entry_lincov`]: the LinCov of one filter on one scenario ([`EntryLinCov`]), after the
//! checks of what it cannot analyse.

use super::epoch::EntryLinCovEpoch;
use super::error::EntryLinCovError;
use super::fusion::FusionRecursion;
use super::options::{LinCovOptions, unsupported_reason};
use super::recursion::Recursion;
use super::truth::{NominalTruth, nominal_truth};
use crate::estimation::Onboard;
use crate::estimation::nav::FilterKind;
use crate::estimation::nav::fusion_setup::local_masks;
use crate::scenario::Scenario;
use crate::sim::monte_carlo::state_names::state_names;
use crate::state_dim::with_state_dim;
use std::sync::Arc;

/// LinCov of one filter on one scenario.
#[derive(Debug, Clone, PartialEq)]
pub struct EntryLinCov {
    /// Filter name.
    pub filter: String,
    /// Filter state names (the trade's).
    pub states: Vec<String>,
    /// The truth's random parameters θ carried (standard normals of the draw).
    pub parameters: Vec<String>,
    /// What this analysis does not model for this scenario.
    pub notes: Vec<String>,
    /// Per epoch.
    pub epochs: Vec<EntryLinCovEpoch>,
}

impl EntryLinCov {
    /// Time average over epochs of `f` (the Monte Carlo's `*_time_avg`).
    pub fn time_avg(&self, f: impl Fn(&EntryLinCovEpoch) -> f64) -> f64 {
        self.epochs.iter().map(f).sum::<f64>() / self.epochs.len().max(1) as f64
    }

    /// `f` at the last epoch (the Monte Carlo's `*_final`).
    pub fn final_value(&self, f: impl Fn(&EntryLinCovEpoch) -> f64) -> f64 {
        self.epochs.last().map_or(f64::NAN, f)
    }

    /// Predicted ANEES divided by its degrees of freedom (compare the Monte Carlo's
    /// `anees / nees_dof`).
    pub fn nees_ratio_time_avg(&self) -> f64 {
        self.time_avg(EntryLinCovEpoch::nees_per_dof)
    }
}

/// LinCov of filter `kind` on `scenario` along its nominal trajectory (first order).
pub fn entry_lincov(
    scenario: &Scenario,
    kind: FilterKind,
) -> Result<EntryLinCov, EntryLinCovError> {
    entry_lincov_with(scenario, kind, LinCovOptions::default())
}

/// LinCov of filter `kind` on `scenario` with `options`.
pub fn entry_lincov_with(
    scenario: &Scenario,
    kind: FilterKind,
    options: LinCovOptions,
) -> Result<EntryLinCov, EntryLinCovError> {
    let onboard = analysable_onboard(scenario, kind)?;
    let n = onboard.state_dim();
    let truth = nominal_truth(scenario, n)?;
    let mut notes = notes(scenario, kind, &truth, options);
    let epochs = match kind {
        FilterKind::Ci | FilterKind::Dcifaif => {
            notes.push(format!(
                "{}: the fusion weights are those of the nominal's onboard covariances (each run's \
                 differ to second order); a local filter dropped after a numerical failure is \
                 not modelled",
                kind.name()
            ));
            with_state_dim(
                n,
                FusionRecursion {
                    scenario,
                    onboard: &onboard,
                    truth: &truth,
                    masks: local_masks(&onboard),
                    feedback: kind == FilterKind::Dcifaif,
                    second_order: options.second_order_mean,
                },
            )?
        }
        _ => with_state_dim(
            n,
            Recursion {
                scenario,
                onboard: &onboard,
                truth: &truth,
                second_order: options.second_order_mean,
            },
        )?,
    };
    let states = state_names(scenario);
    let epochs = epochs.map_err(|e| name_the_state(e, &states))?;
    Ok(EntryLinCov {
        filter: kind.name().into(),
        states,
        parameters: truth.params.clone(),
        notes,
        epochs,
    })
}

/// The onboard view filter `kind` flies on `scenario`, or why LinCov cannot analyse the pair:
/// a filter whose gain is not linear in the measurements, one that does not fit, an innovation
/// gate, sensor faults.
fn analysable_onboard(
    scenario: &Scenario,
    kind: FilterKind,
) -> Result<Arc<Onboard>, EntryLinCovError> {
    if let Some(reason) = unsupported_reason(kind) {
        return Err(EntryLinCovError::UnsupportedFilter {
            filter: kind.name().into(),
            reason: reason.into(),
        });
    }
    let refuse = |field: &str, value: String, reason: &str| EntryLinCovError::UnsupportedScenario {
        scenario: scenario.config.name.clone(),
        field: field.into(),
        value,
        reason: reason.into(),
    };
    kind.check_fits(&scenario.onboard)
        .map_err(|e| refuse("filter", kind.name().into(), &e.to_string()))?;
    let onboard = scenario.onboard.for_filter(kind);
    if onboard.tuning.gating.is_some_and(|g| g.enabled) {
        return Err(refuse(
            "filter.gating.enabled",
            "true".into(),
            "an innovation gate is a decision on the measured innovations, not linear; \
             allowed: false",
        ));
    }
    if !scenario.faults.is_empty() {
        return Err(refuse(
            "faults",
            format!("{} fault(s)", scenario.faults.len()),
            "random sensor faults and outliers are not Gaussian; allowed: none",
        ));
    }
    Ok(onboard)
}

/// What this analysis does not model for `scenario` and `kind`, or carries beyond the first
/// order ([`EntryLinCov::notes`]; the fusion filters' note is added with their recursion).
fn notes(
    scenario: &Scenario,
    kind: FilterKind,
    truth: &NominalTruth,
    options: LinCovOptions,
) -> Vec<String> {
    let mut notes = Vec::new();
    if kind == FilterKind::Ukf {
        notes.push(
            "ukf: analysed as its EKF equivalent (with the UKF's own tuning): along the nominal \
             its sigma-point mean, covariance and gain equal the EKF's to first order in the \
             dispersions; the sigma points' second-order terms are not modelled"
                .to_string(),
        );
    }
    if scenario.config.truth.perturbation.is_some() {
        notes.push(
            "truth.perturbation: carried as the AR(1) grid's standard normals; the nominal flies \
             z = 0, the median profile ρ_mean·exp(−s²/2), not the mean"
                .to_string(),
        );
    }
    if scenario
        .truth_profiles
        .as_ref()
        .is_some_and(|c| c.is_cycling())
    {
        notes.push("truth profiles cycle over runs; LinCov flies profile 0 only".to_string());
    }
    let d = &scenario.config.dispersions;
    if d.density_bias_clip > 0.0 && d.density_bias != 0.0 {
        notes.push(format!(
            "dispersions.density_bias_clip = {}: the clip of the density bias is not modelled",
            d.density_bias_clip
        ));
    }
    if let Some(t) = truth.truncated {
        notes.push(format!(
            "a dispersed run ends before the nominal: epochs from t = {t} s are left out"
        ));
    }
    if options.second_order_mean {
        notes.push(
            "second-order mean: the time update's mean carries ½ Σ ∂²F/∂x_a∂x_b (E[δx̂δx̂ᵀ] − \
             E[δxδxᵀ])_ab and a single update's the same term of h, from central differences of \
             the filter's Φ and H; the covariance stays first order"
                .to_string(),
        );
    }
    notes
}

/// A second-order failure names the state by index deep in the recursion (`#i`): name it with
/// `states`.
fn name_the_state(e: EntryLinCovError, states: &[String]) -> EntryLinCovError {
    match e {
        EntryLinCovError::SecondOrder {
            t,
            state,
            step,
            reason,
        } => EntryLinCovError::SecondOrder {
            t,
            state: state
                .strip_prefix('#')
                .and_then(|i| i.parse::<usize>().ok())
                .and_then(|i| states.get(i).cloned())
                .unwrap_or(state),
            step,
            reason,
        },
        other => other,
    }
}
