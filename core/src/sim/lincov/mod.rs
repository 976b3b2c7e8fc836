//! LinCov of the *actual* navigation filter along a scenario's nominal entry trajectory: the
//! true estimation-error statistics a Monte Carlo of the same filter would measure, model
//! mismatch included, in one pass (Maybeck, *Stochastic Models, Estimation and Control* vol. 1,
//! 1979, ch. 6, truth-model/filter-model performance analysis; Geller, J. Spacecraft Rockets
//! 43(6), 2006, eq. 20–38, the nonlinear form linearised about a nominal). [`crate::lincov`] is
//! the exact linear form this one reduces to for linear models.
//!
//! # The augmented state
//!
//! The truth flies no process noise, so its random part is a set of constants θ: the standard
//! normals a Monte Carlo draw turns into the initial-state, C_D S/m, L/D and density-bias
//! dispersions ([`crate::scenario::Scenario::disperse_with`]) and, where the truth has one, its
//! density perturbation (Cov θ = I). Its state in the
//! filter's coordinates (truth-equivalent parameters included) is x_k = x̄_k + S_k θ and its
//! measurements z_k = z̄_k + Z_k θ + v_k (noise v ~ N(0, R_t), the truth's own σ), with x̄, z̄ the
//! noise-free nominal run and S_k, Z_k from central differences of whole truth runs
//! (`truth.rs`). Truth-only parameters (a dispersed B when the filter does not estimate it, the
//! density bias of a filter without a density state) are therefore in θ whether or not the
//! filter has a state for them; a deterministic mismatch (the accelerometer bias, a filter
//! C_D S/m or atmosphere that differs from the truth's) enters as a mean error.
//!
//! The filter's deviation from the nominal, δx̂ = x̂ − x̄, and θ form the augmented vector
//! \[θ; δx̂\]; its second moments C_θθ = I, C_θĥ = E\[θ δx̂ᵀ\], C_ĥĥ and the mean m = E\[δx̂\] are
//! propagated with the filter's own models linearised along the nominal:
//! * time update (Maybeck eq. 6-10 with a constant truth): x̂⁻ = f_f(x̂) ≈ f_f(x̄_{k−1}) + Φ_f δx̂,
//!   so δx̂⁻ = Φ_f δx̂ + d_k with the model-mismatch drift d_k = f_f(x̄_{k−1}) − x̄_k; Φ_f is the
//!   EKF's own transition (same RK4 sub-steps, [`crate::estimation::nav::EkfNav::substep`]);
//! * measurement update, one scalar at a time as the EKF processes them (Joseph form,
//!   consider rows of the gain zero): with the filter's H_f = ∂h_f/∂x at x̄_k, gain
//!   K = P⁻H_fᵀ/(H_f P⁻ H_fᵀ + R_f) from the filter's own P computed along the nominal (P does not
//!   depend on the dispersions to first order), A = I − K H_f, and the residual of the models at
//!   the nominal r = z̄ − h_f(x̄):
//!   δx̂⁺ = A δx̂⁻ + K (Zθ + v + r), so C_θĥ ← C_θĥ Aᵀ + ζKᵀ,
//!   C_ĥĥ ← A C_ĥĥ Aᵀ + A C_ĥθ ζ Kᵀ + K ζᵀ C_θĥ Aᵀ + K (ζᵀζ + R_t) Kᵀ, m ← A m + K r.
//!
//! The estimation error e = δx̂ − S_k θ then has E\[eeᵀ\] = C_ĥĥ − C_ĥθ S_kᵀ − S_k C_θĥ +
//! S_k S_kᵀ + m mᵀ (the mean-square matrix, bias included, as a Monte Carlo RMSE sees it).
//!
//! # The iterated EKF
//!
//! The iterated update (`filter.update_iterations` > 1) relinearises at its iterate x_i and
//! applies x̂⁺ = x̂⁻ + K_i(z − h(x_i) − H_i(x̂⁻ − x_i)). Along the nominal, x_i = x̄ + O(δ), so to
//! first order in the dispersions H_i = H(x̄) and the iterated update is the EKF's linearised at
//! x̄: LinCov analyses both the same way. What the iterations buy (less linearisation error for
//! large initial errors) is second order and is the gap between this and a Monte Carlo.
//!
//! # The fusion filters (`ci`, `dcifaif`)
//!
//! [`crate::estimation::nav::FusionNav`] runs one local EKF per beacon (the IMU plus that
//! beacon's ranges) and fuses them by covariance intersection (seed 000 eq. 19–22). Each local
//! is the EKF above along the nominal, with its own P and gains; the recursion keeps the joint
//! moments of \[θ; δx̂_1 … δx̂_M\], whose cross-blocks are the locals' correlations through the
//! common start, the shared IMU noise and θ. The CI weights come from the onboard covariances by
//! the filter's own code, so along the nominal the fused deviation is the linear combination
//! δx̂_CI = Σ W_i δx̂_i with W_i = ω_i P_CI P_i⁻¹ (Σ W_i = I); with information feedback
//! (`dcifaif`) every local restarts from it, and with `fusion_covariance = "exact"` each local's
//! update of the common prior is the filter's batch update. The NEES uses the fused covariance the
//! filter reports (P_CI, or the exact covariance).
//!
//! # What it does not model
//!
//! Listed per run in [`EntryLinCov::notes`]: profile cycling of a table of stacked profiles, the
//! clip of the density bias, and that with a truth density perturbation the nominal flies its
//! median profile. Not listed: visibility changes of dispersed trajectories (the nominal's
//! schedule is used).
//!
//! A truth density perturbation (`truth.perturbation`, the altitude-correlated Gauss–Markov
//! factor of [`crate::atmosphere::Perturbed`]) is in θ too: one standard normal per point of its
//! AR(1) grid at or below the highest altitude flown ([`crate::atmosphere::Perturbed::from_normals`]),
//! so its contribution is a sum over those columns of S and Z like any other parameter's. Filters whose
//! gain depends on the measurements or on something beside their own P are refused
//! ([`unsupported_reason`]), and so is an innovation gate or a scenario with sensor faults.

mod epoch;
mod fusion;
mod joint;
mod recursion;
mod second_order;
mod truth;

use super::engine::SimError;
use crate::estimation::nav::FilterKind;
use crate::estimation::nav::fusion::local_masks;
use crate::scenario::Scenario;
use crate::state_dim::{UnsupportedDimension, with_state_dim};
use thiserror::Error;

pub use epoch::EntryLinCovEpoch;

/// Why a LinCov cannot be formed.
#[derive(Debug, Error, Clone, PartialEq)]
pub enum EntryLinCovError {
    /// The filter's gain is not a function of its own covariance along the nominal.
    #[error(
        "LinCov cannot analyse filter '{filter}': {reason}; supported filters: ekf, ukf, ci, dcifaif"
    )]
    UnsupportedFilter {
        /// Filter name.
        filter: String,
        /// Why.
        reason: String,
    },
    /// Something in the scenario LinCov cannot linearise.
    #[error("LinCov cannot analyse scenario '{scenario}': {field} = {value} ({reason})")]
    UnsupportedScenario {
        /// Scenario name.
        scenario: String,
        /// The configuration field.
        field: String,
        /// Its value.
        value: String,
        /// Why.
        reason: String,
    },
    /// The nominal truth failed.
    #[error("the nominal truth failed: {0}")]
    Truth(#[from] SimError),
    /// The nominal run has no measurement epoch.
    #[error("the nominal run of scenario '{0}' has no measurement epoch")]
    NoEpochs(String),
    /// A ±h run has a different epoch schedule (a sensor period that changed).
    #[error("the run with parameter {parameter} perturbed has no epoch at t = {t} s")]
    Schedule {
        /// Parameter.
        parameter: String,
        /// Epoch \[s\].
        t: f64,
    },
    /// A value became non-finite.
    #[error("{what} became non-finite at t = {t} s")]
    NonFinite {
        /// What.
        what: String,
        /// Epoch \[s\].
        t: f64,
    },
    /// The filter could not be built or its covariance failed.
    #[error("the filter failed along the nominal: {0}")]
    Filter(String),
    /// The second-order terms could not be differenced (`LinCovOptions::second_order_mean`).
    #[error(
        "the second-order mean at t = {t} s: the filter's model fails {step:.3e} from the nominal \
         in state {state} ({reason}): the deviations are too large for a second-order expansion \
         (a Monte Carlo of this filter is likely to diverge); run without --second-order-mean"
    )]
    SecondOrder {
        /// Epoch \[s\].
        t: f64,
        /// Name of the state differenced.
        state: String,
        /// Its step.
        step: f64,
        /// What failed.
        reason: String,
    },
    /// The filter dimension is not supported.
    #[error(transparent)]
    Dimension(#[from] UnsupportedDimension),
}

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
    let n = onboard.state_dim();
    let truth = truth::nominal_truth(scenario, n)?;
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
                fusion::FusionRecursion {
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
            recursion::Recursion {
                scenario,
                onboard: &onboard,
                truth: &truth,
                second_order: options.second_order_mean,
            },
        )?,
    };
    let states = super::monte_carlo::state_names(scenario);
    // A second-order failure names the state by index deep in the recursion: name it here.
    let epochs = epochs.map_err(|e| match e {
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
    })?;
    Ok(EntryLinCov {
        filter: kind.name().into(),
        states,
        parameters: truth.params.clone(),
        notes,
        epochs,
    })
}
