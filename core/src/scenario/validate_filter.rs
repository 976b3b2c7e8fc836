//! Checks of the `[filter]` section: its state layout (augmented and consider states, P0, Q and
//! start values) and its tuning (iterations, noise factors, UKF parameters, model bank).

use super::config::{FilterConfig, NoiseInflation, ProcessNoiseModel, ScenarioConfig};
use super::error::ScenarioError;
use super::validate_range::{Checker, R, Range};
use super::validate_state::{cd_s_over_m_range, lift_to_drag_range};
use crate::dynamics::AugmentedParam;
use crate::estimation::nav::FilterKind;
use crate::planet::Planet;

/// Largest `filter.update_iterations` (each iteration is one more linearisation per update).
pub const MAX_UPDATE_ITERATIONS: usize = 20;

/// Allowed density biases Δ (ρ = ρ_model (1 + Δ)).
pub(super) fn density_bias_range() -> Range {
    Range::gt(-1.0).lt(10.0).note("density stays positive")
}

impl ScenarioConfig {
    /// `[filter]`: models, state layout, tuning, density adaptation.
    pub(super) fn check_filter(&self, planet: &Planet, c: &mut Checker) -> R {
        let f = &self.filter;
        f.vehicle.check("filter.vehicle", c)?;
        f.atmosphere.validate("filter.atmosphere")?;
        if let Some(s) = &f.initial {
            s.check_state("filter.initial", planet, c)?;
        }
        f.check_layout(c)?;
        let all = f.state_params();
        if all.iter().any(|a| a.accel_axis().is_some()) && self.sensors.imu.is_none() {
            return Err(ScenarioError::invalid(
                "filter.augment",
                "accelerometer-bias states need an accelerometer ([sensors.imu])",
            ));
        }
        f.check_tuning(c)?;
        f.check_per_filter_tuning(c)?;
        if let Some(d) = &f.density {
            d.check("filter.density", c)?;
        }
        if let Some(g) = &f.gating {
            c.range(
                "filter.gating.probability",
                g.probability,
                Range::ge(0.9).lt(1.0).note("the χ² gate's probability"),
            )?;
            c.range(
                "filter.gating.exclude_after",
                g.exclude_after as f64,
                Range::ge(1.0).le(1000.0).unit("epochs"),
            )?;
            c.range(
                "filter.gating.readmit_after",
                g.readmit_after as f64,
                Range::ge(1.0).le(100_000.0).unit("epochs"),
            )?;
        }
        Ok(())
    }
}

impl FilterConfig {
    /// Augmented and consider states, P0 and Q diagonals and the start values.
    fn check_layout(&self, c: &mut Checker) -> R {
        let all = self.state_params();
        for (k, a) in all.iter().enumerate() {
            if all[..k].contains(a) {
                return Err(ScenarioError::invalid(
                    "filter.augment",
                    format!(
                        "'{}' is listed twice in filter.augment and filter.consider",
                        a.config_name()
                    ),
                ));
            }
        }
        if all.contains(&AugmentedParam::Rho0) && all.contains(&AugmentedParam::DensityBias) {
            return Err(ScenarioError::invalid(
                "filter.augment",
                "rho0 and density-bias both scale the density: use one of them",
            ));
        }
        self.check_covariances(c)?;
        for (field, list, params, values) in [
            (
                "initial_augmented",
                "augment",
                &self.augment,
                &self.initial_augmented,
            ),
            (
                "initial_consider",
                "consider",
                &self.consider,
                &self.initial_consider,
            ),
        ] {
            if values.len() != params.len() {
                return Err(ScenarioError::invalid(
                    format!("filter.{field}"),
                    format!(
                        "has {} values but filter.{list} lists {} states",
                        values.len(),
                        params.len()
                    ),
                ));
            }
            for (k, (a, v)) in params.iter().zip(values.iter()).enumerate() {
                c.range(format!("filter.{field}[{k}]"), *v, start_value_range(*a))?;
            }
        }
        if all.contains(&AugmentedParam::Rho0) && self.atmosphere.reference_density().is_none() {
            return Err(ScenarioError::invalid(
                "filter.augment",
                "rho0 can only be augmented with an exponential filter atmosphere",
            ));
        }
        Ok(())
    }

    /// `p0_diag` and `q_diag`: one variance per state.
    fn check_covariances(&self, c: &mut Checker) -> R {
        let n = self.state_dim();
        for (name, v) in [
            ("filter.p0_diag", &self.p0_diag),
            ("filter.q_diag", &self.q_diag),
        ] {
            if v.len() != n {
                return Err(ScenarioError::invalid(
                    name,
                    format!(
                        "has {} entries but the filter state has {n} (6 kinematic + {} augmented + {} consider)",
                        v.len(),
                        self.augment.len(),
                        self.consider.len()
                    ),
                ));
            }
        }
        for (k, p) in self.p0_diag.iter().enumerate() {
            let range = Range::gt(0.0).note("a variance");
            c.range(format!("filter.p0_diag[{k}]"), *p, range)?;
        }
        check_q_diag("filter.q_diag", &self.q_diag, c)?;
        check_process_noise("filter.process_noise", &self.process_noise, self, c)
    }

    /// Whether the filter carries a density state (`density-bias` or `rho0`, augmented or
    /// consider) that a process-noise model's `density_sigma` can drive.
    fn has_density_state(&self) -> bool {
        self.augment
            .iter()
            .chain(&self.consider)
            .any(|a| matches!(a, AugmentedParam::DensityBias | AugmentedParam::Rho0))
    }

    /// `[filter.tuned.<name>]`: a known filter name, a full Q diagonal, valid noise factors.
    fn check_per_filter_tuning(&self, c: &mut Checker) -> R {
        let n = self.state_dim();
        for (name, t) in &self.tuned {
            let field = format!("filter.tuned.{name}");
            if let Err(e) = FilterKind::parse(name) {
                return Err(ScenarioError::invalid(field, e.to_string()));
            }
            if let Some(q) = &t.q_diag {
                let field = format!("{field}.q_diag");
                if q.len() != n {
                    return Err(ScenarioError::invalid(
                        field,
                        format!(
                            "has {} entries but the filter state has {n} (as filter.q_diag)",
                            q.len()
                        ),
                    ));
                }
                check_q_diag(&field, q, c)?;
            }
            if let Some(m) = &t.process_noise {
                check_process_noise(&format!("{field}.process_noise"), m, self, c)?;
            }
            if let Some(inf) = &t.noise_inflation {
                check_inflation(&format!("{field}.noise_inflation"), inf, c)?;
            }
        }
        Ok(())
    }

    /// Iterations, assumed noise, Gauss–Markov time, UKF parameters, model bank.
    fn check_tuning(&self, c: &mut Checker) -> R {
        c.range(
            "filter.update_iterations",
            self.update_iterations,
            Range::ge(1.0)
                .le(MAX_UPDATE_ITERATIONS as f64)
                .note("1 is the standard EKF, more iterate it"),
        )?;
        if let Some(s) = self.imu_sigma_mps2 {
            let range = Range::gt(0.0).lt(10.0).unit("m/s²");
            c.range("filter.imu_sigma_mps2", s, range)?;
        }
        if let Some(n) = &self.noise_inflation {
            check_inflation("filter.noise_inflation", n, c)?;
        }
        if let Some(tau) = self.accel_bias_tau_s {
            let range = Range::gt(0.0)
                .unit("s")
                .note("the Gauss-Markov time constant");
            c.range("filter.accel_bias_tau_s", tau, range)?;
        }
        let ukf = &self.ukf;
        c.range("filter.ukf.alpha", ukf.alpha, Range::gt(0.0).le(1.0))?;
        c.range("filter.ukf.beta", ukf.beta, Range::ge(0.0).lt(10.0))?;
        if let Some(k) = ukf.kappa {
            c.range("filter.ukf.kappa", k, Range::within(100.0))?;
        }
        for (k, d) in self.model_bank_density_bias.iter().enumerate() {
            let field = format!("filter.model_bank_density_bias[{k}]");
            c.range(field, *d, density_bias_range())?;
        }
        Ok(())
    }
}

/// Allowed start value of an augmented or consider state.
fn start_value_range(a: AugmentedParam) -> Range {
    match a {
        AugmentedParam::Rho0 => Range::gt(0.0).lt(1.0).unit("kg/m³").of("ρ0"),
        AugmentedParam::LiftToDrag => lift_to_drag_range().of("L/D"),
        AugmentedParam::CdSOverM => cd_s_over_m_range().of("C_D S/m"),
        AugmentedParam::DensityBias => density_bias_range().of("Δ"),
        AugmentedParam::AccelBiasX | AugmentedParam::AccelBiasY | AugmentedParam::AccelBiasZ => {
            Range::within(10.0).unit("m/s²").of("an accelerometer bias")
        }
    }
}

/// Every entry of a process-noise diagonal is a variance (≥ 0).
fn check_q_diag(field: &str, q: &[f64], c: &mut Checker) -> R {
    for (k, v) in q.iter().enumerate() {
        let range = Range::ge(0.0).note("a variance");
        c.range(format!("{field}[{k}]"), *v, range)?;
    }
    Ok(())
}

/// The load-scaled model: fractions in [0, MAX_AERO_FRACTION], a floor in [0, 10] m/s², exactly one positive
/// correlation (a time up to 1000 s or a length up to 100 km).
fn check_process_noise(
    field: &str,
    m: &ProcessNoiseModel,
    filter: &FilterConfig,
    c: &mut Checker,
) -> R {
    let ProcessNoiseModel::AeroScaled(a) = m else {
        return Ok(());
    };
    if a.density_sigma > 0.0 && !filter.has_density_state() {
        return Err(ScenarioError::invalid(
            format!("{field}.density_sigma"),
            format!(
                "= {} needs a density state to drive: add \"density-bias\" or \"rho0\" to \
                 filter.augment (or filter.consider)",
                a.density_sigma
            ),
        ));
    }
    for (k, f) in a.fraction.iter().enumerate() {
        let range = Range::ge(0.0)
            .le(super::config::MAX_AERO_FRACTION)
            .note("1-sigma of the unmodelled specific force over |a_aero|");
        c.range(format!("{field}.fraction[{k}]"), *f, range)?;
    }
    let range = Range::ge(0.0).le(10.0).unit("m/s²");
    c.range(format!("{field}.floor_mps2"), a.floor_mps2, range)?;
    let range = Range::ge(0.0)
        .le(crate::estimation::MAX_DENSITY_SIGMA)
        .note("1-sigma of the relative density error");
    c.range(format!("{field}.density_sigma"), a.density_sigma, range)?;
    match (a.correlation_time_s, a.correlation_length_m) {
        (Some(t), None) => {
            let range = Range::gt(0.0).le(1000.0).unit("s");
            c.range(format!("{field}.correlation_time_s"), t, range)
        }
        (None, Some(l)) => {
            let range = Range::gt(0.0).le(100e3).unit("m");
            c.range(format!("{field}.correlation_length_m"), l, range)
        }
        _ => Err(ScenarioError::invalid(
            field,
            "needs exactly one of correlation_time_s and correlation_length_m",
        )),
    }
}

/// Every factor on an assumed noise lies in (0, 1000].
fn check_inflation(field: &str, n: &NoiseInflation, c: &mut Checker) -> R {
    for (name, v) in [
        ("accel", n.accel),
        ("dynamic_pressure", n.dynamic_pressure),
        ("heating", n.heating),
        ("range", n.range),
        ("range_rate", n.range_rate),
    ] {
        let range = Range::gt(0.0)
            .le(super::config::MAX_NOISE_INFLATION)
            .note("a factor on the assumed 1-sigma noise");
        c.range(format!("{field}.{name}"), v, range)?;
    }
    Ok(())
}
