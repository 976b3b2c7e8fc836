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

mod ekf_steps;
mod entry_lincov;
mod epoch;
mod error;
mod fusion;
mod fusion_exact;
mod joint;
mod options;
mod recursion;
mod second_order;
mod statistics;
mod truth;

pub use entry_lincov::{EntryLinCov, entry_lincov, entry_lincov_with};
pub use epoch::EntryLinCovEpoch;
pub use error::EntryLinCovError;
pub use options::{LinCovOptions, unsupported_reason};
