//! Physical range checks for a [`ScenarioConfig`]; every error names field, value and range.

use super::config::*;
use super::error::ScenarioError;
use crate::dynamics::AugmentedParam;
use crate::planet::Planet;

pub(super) type R = Result<(), ScenarioError>;

/// Largest `filter.update_iterations` (each iteration is one more linearisation per update).
pub const MAX_UPDATE_ITERATIONS: usize = 20;

pub(super) fn within(field: &str, v: f64, lo: f64, hi: f64, allowed: &str) -> R {
    if v.is_finite() && v > lo && v < hi {
        Ok(())
    } else {
        Err(ScenarioError::range(field, v, allowed))
    }
}

/// Is `period` an integer multiple of `step` (to 1e-9 relative)?
pub fn is_multiple(period: f64, step: f64) -> bool {
    let n = (period / step).round();
    n >= 1.0 && (period - n * step).abs() <= 1e-9 * period.max(step)
}

impl PlanetConfig {
    /// The planet these overrides give, starting from Mars.
    pub fn resolve(&self) -> Planet {
        let mut p = Planet::MARS;
        if let Some(mu) = self.mu_m3s2 {
            p.mu = mu;
        }
        if let Some(r) = self.radius_km {
            p.radius = r * 1e3;
        }
        if let Some(w) = self.rotation_rate_rad_s {
            p.rotation_rate = w;
        }
        p
    }

    fn validate(&self) -> R {
        if let Some(mu) = self.mu_m3s2 {
            within(
                "planet.mu_m3s2",
                mu,
                1e9,
                1e17,
                "must be > 1e9 and < 1e17 m³/s²",
            )?;
        }
        if let Some(r) = self.radius_km {
            within(
                "planet.radius_km",
                r,
                100.0,
                1e5,
                "must be > 100 and < 100000 km",
            )?;
        }
        if let Some(w) = self.rotation_rate_rad_s {
            within(
                "planet.rotation_rate_rad_s",
                w,
                -1e-3,
                1e-3,
                "must be within ±1e-3 rad/s",
            )?;
        }
        Ok(())
    }
}

/// Which complete form a [`StateConfig`] has.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StateForm {
    /// radius/lon/lat/speed/fpa/heading.
    Spherical,
    /// position/velocity.
    Cartesian,
}

impl StateConfig {
    /// The form of this state, or an error naming what is missing or mixed.
    pub fn form(&self, field: &str) -> Result<StateForm, ScenarioError> {
        let sph = [
            self.radius_km,
            self.lon_deg,
            self.lat_deg,
            self.speed_mps,
            self.fpa_deg,
            self.heading_deg,
        ];
        let n_sph = sph.iter().filter(|v| v.is_some()).count();
        let n_cart = self.position_km.is_some() as usize + self.velocity_mps.is_some() as usize;
        match (n_sph, n_cart) {
            (6, 0) => Ok(StateForm::Spherical),
            (0, 2) => Ok(StateForm::Cartesian),
            (0, 0) => Err(ScenarioError::invalid(
                field,
                "empty: give radius_km, lon_deg, lat_deg, speed_mps, fpa_deg, heading_deg, or position_km and velocity_mps",
            )),
            (a, b) if a > 0 && b > 0 => Err(ScenarioError::invalid(
                field,
                "mixes spherical (radius_km…) and Cartesian (position_km, velocity_mps) fields: give one form",
            )),
            _ => Err(ScenarioError::invalid(
                field,
                "incomplete: a spherical state needs all of radius_km, lon_deg, lat_deg, speed_mps, fpa_deg, heading_deg; a Cartesian one needs position_km and velocity_mps",
            )),
        }
    }

    fn validate_state(&self, field: &str, planet: &Planet) -> R {
        let r_km = planet.radius / 1e3;
        match self.form(field)? {
            StateForm::Spherical => {
                let r = self.radius_km.unwrap_or_default();
                let f = format!("{field}.radius_km");
                within(
                    &f,
                    r,
                    r_km,
                    10.0 * r_km,
                    &format!("must be above the surface ({r_km} km) and below 10 planet radii"),
                )?;
                within(
                    &format!("{field}.lat_deg"),
                    self.lat_deg.unwrap_or_default(),
                    -90.0,
                    90.0,
                    "must be strictly within ±90°",
                )?;
                within(
                    &format!("{field}.lon_deg"),
                    self.lon_deg.unwrap_or_default(),
                    -360.001,
                    360.001,
                    "must be within ±360°",
                )?;
                within(
                    &format!("{field}.speed_mps"),
                    self.speed_mps.unwrap_or_default(),
                    0.0,
                    3e4,
                    "must be > 0 and < 30000 m/s",
                )?;
                within(
                    &format!("{field}.fpa_deg"),
                    self.fpa_deg.unwrap_or_default(),
                    -90.0,
                    90.0,
                    "must be strictly within ±90°",
                )?;
                within(
                    &format!("{field}.heading_deg"),
                    self.heading_deg.unwrap_or_default(),
                    -360.001,
                    360.001,
                    "must be within ±360°",
                )?;
            }
            StateForm::Cartesian => {
                let p = self.position_km.unwrap_or_default();
                let v = self.velocity_mps.unwrap_or_default();
                let rn = (p[0] * p[0] + p[1] * p[1] + p[2] * p[2]).sqrt();
                let vn = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                let f = format!("{field}.position_km");
                within(
                    &f,
                    rn,
                    r_km,
                    10.0 * r_km,
                    &format!(
                        "its norm must be above the surface ({r_km} km) and below 10 planet radii"
                    ),
                )?;
                within(
                    &format!("{field}.velocity_mps"),
                    vn,
                    0.0,
                    3e4,
                    "its norm must be > 0 and < 30000 m/s",
                )?;
            }
        }
        Ok(())
    }

    fn validate_sigma(&self, field: &str) -> R {
        let all = [
            ("radius_km", self.radius_km),
            ("lon_deg", self.lon_deg),
            ("lat_deg", self.lat_deg),
            ("speed_mps", self.speed_mps),
            ("fpa_deg", self.fpa_deg),
            ("heading_deg", self.heading_deg),
        ];
        for (name, v) in all {
            if let Some(v) = v {
                within(
                    &format!("{field}.{name}"),
                    v,
                    -f64::MIN_POSITIVE,
                    1e4,
                    "a 1σ must be >= 0 and < 1e4",
                )?;
            }
        }
        for (name, v) in [
            ("position_km", self.position_km),
            ("velocity_mps", self.velocity_mps),
        ] {
            if let Some(v) = v {
                for (k, x) in v.iter().enumerate() {
                    within(
                        &format!("{field}.{name}[{k}]"),
                        *x,
                        -f64::MIN_POSITIVE,
                        1e4,
                        "a 1σ must be >= 0 and < 1e4",
                    )?;
                }
            }
        }
        self.form(field).map(|_| ())
    }
}

impl VehicleConfig {
    /// C_D S/m [m²/kg] from whichever field is given.
    pub fn cd_s_over_m(&self) -> f64 {
        match (self.cd_s_over_m_m2kg, self.ballistic_coefficient_kgm2) {
            (Some(b), _) => b,
            (None, Some(beta)) => 1.0 / beta,
            (None, None) => f64::NAN,
        }
    }

    fn validate(&self, field: &str) -> R {
        match (self.cd_s_over_m_m2kg, self.ballistic_coefficient_kgm2) {
            (Some(b), None) => within(
                &format!("{field}.cd_s_over_m_m2kg"),
                b,
                0.0,
                1.0,
                "must be > 0 and < 1 m²/kg (mass and area positive)",
            )?,
            (None, Some(beta)) => within(
                &format!("{field}.ballistic_coefficient_kgm2"),
                beta,
                0.0,
                1e5,
                "must be > 0 and < 1e5 kg/m² (mass and area positive)",
            )?,
            (Some(_), Some(_)) => {
                return Err(ScenarioError::invalid(
                    field,
                    "give cd_s_over_m_m2kg or ballistic_coefficient_kgm2, not both",
                ));
            }
            (None, None) => {
                return Err(ScenarioError::invalid(
                    field,
                    "missing cd_s_over_m_m2kg (or ballistic_coefficient_kgm2)",
                ));
            }
        }
        within(
            &format!("{field}.lift_to_drag"),
            self.lift_to_drag,
            -0.001,
            3.0,
            "must be >= 0 and < 3",
        )
    }
}

impl ScenarioConfig {
    /// Check every field; the first problem found is returned.
    pub fn validate(&self) -> R {
        if self.name.trim().is_empty() {
            return Err(ScenarioError::invalid("name", "must not be empty"));
        }
        self.planet.validate()?;
        let planet = self.planet.resolve();
        let t = &self.timing;
        within(
            "timing.duration_s",
            t.duration_s,
            0.0,
            7200.0,
            "must be > 0 and <= 7200 s",
        )?;
        within(
            "timing.truth_step_s",
            t.truth_step_s,
            0.0,
            10.0,
            "must be > 0 and <= 10 s",
        )?;
        if t.truth_step_s > t.duration_s {
            return Err(ScenarioError::range(
                "timing.truth_step_s",
                t.truth_step_s,
                format!("must not exceed timing.duration_s = {}", t.duration_s),
            ));
        }
        within(
            "timing.filter_step_s",
            t.filter_step_s,
            0.0,
            60.0,
            "must be > 0 and <= 60 s",
        )?;
        if !is_multiple(t.filter_step_s, t.truth_step_s) {
            return Err(ScenarioError::range(
                "timing.filter_step_s",
                t.filter_step_s,
                format!(
                    "must be an integer multiple of timing.truth_step_s = {}",
                    t.truth_step_s
                ),
            ));
        }
        if let Some(s) = t.stop_speed_mps {
            within(
                "timing.stop_speed_mps",
                s,
                0.0,
                3e4,
                "must be > 0 and < 30000 m/s",
            )?;
        }

        // Truth.
        self.truth
            .initial
            .validate_state("truth.initial", &planet)?;
        self.truth.vehicle.validate("truth.vehicle")?;
        self.truth.atmosphere.validate("truth.atmosphere")?;
        if let Some(p) = &self.truth.perturbation {
            p.validate("truth.perturbation")?;
        }
        within(
            "truth.density_bias",
            self.truth.density_bias,
            -1.0,
            10.0,
            "must be > -1 (density stays positive) and < 10",
        )?;
        within(
            "truth.bank_deg",
            self.truth.bank_deg,
            -180.001,
            180.001,
            "must be within ±180°",
        )?;

        // Filter.
        let f = &self.filter;
        f.vehicle.validate("filter.vehicle")?;
        f.atmosphere.validate("filter.atmosphere")?;
        if let Some(s) = &f.initial {
            s.validate_state("filter.initial", &planet)?;
        }
        let all = f.state_params();
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
        let n = f.state_dim();
        for (name, v) in [("filter.p0_diag", &f.p0_diag), ("filter.q_diag", &f.q_diag)] {
            if v.len() != n {
                return Err(ScenarioError::invalid(
                    name,
                    format!(
                        "has {} entries but the filter state has {n} (6 kinematic + {} augmented + {} consider)",
                        v.len(),
                        f.augment.len(),
                        f.consider.len()
                    ),
                ));
            }
        }
        for (k, p) in f.p0_diag.iter().enumerate() {
            within(
                &format!("filter.p0_diag[{k}]"),
                *p,
                0.0,
                1e20,
                "must be > 0 (a variance) and finite",
            )?;
        }
        for (k, q) in f.q_diag.iter().enumerate() {
            within(
                &format!("filter.q_diag[{k}]"),
                *q,
                -f64::MIN_POSITIVE,
                1e20,
                "must be >= 0 (a variance) and finite",
            )?;
        }
        for (field, params, values) in [
            ("initial_augmented", &f.augment, &f.initial_augmented),
            ("initial_consider", &f.consider, &f.initial_consider),
        ] {
            if values.len() != params.len() {
                return Err(ScenarioError::invalid(
                    format!("filter.{field}"),
                    format!(
                        "has {} values but filter.{} lists {} states",
                        values.len(),
                        if field == "initial_augmented" {
                            "augment"
                        } else {
                            "consider"
                        },
                        params.len()
                    ),
                ));
            }
            for (k, (a, v)) in params.iter().zip(values.iter()).enumerate() {
                validate_augmented_value(&format!("filter.{field}[{k}]"), *a, *v)?;
            }
        }
        if all.contains(&AugmentedParam::Rho0)
            && self.filter.atmosphere.reference_density().is_none()
        {
            return Err(ScenarioError::invalid(
                "filter.augment",
                "rho0 can only be augmented with an exponential filter atmosphere",
            ));
        }
        if all.iter().any(|a| a.accel_axis().is_some()) && self.sensors.imu.is_none() {
            return Err(ScenarioError::invalid(
                "filter.augment",
                "accelerometer-bias states need an accelerometer ([sensors.imu])",
            ));
        }
        if !(1..=MAX_UPDATE_ITERATIONS).contains(&f.update_iterations) {
            return Err(ScenarioError::invalid(
                "filter.update_iterations",
                format!(
                    "is {}; must be 1 (the standard EKF) to {MAX_UPDATE_ITERATIONS} (iterated EKF)",
                    f.update_iterations
                ),
            ));
        }
        if let Some(n) = &f.noise_inflation {
            for (name, v) in [
                ("accel", n.accel),
                ("dynamic_pressure", n.dynamic_pressure),
                ("heating", n.heating),
                ("range", n.range),
                ("range_rate", n.range_rate),
            ] {
                within(
                    &format!("filter.noise_inflation.{name}"),
                    v,
                    0.0,
                    1e3,
                    "must be > 0 and <= 1000 (a factor on the assumed 1-sigma noise)",
                )?;
            }
        }
        if let Some(tau) = f.accel_bias_tau_s {
            within(
                "filter.accel_bias_tau_s",
                tau,
                0.0,
                1e9,
                "must be > 0 s (the Gauss-Markov time constant) and finite",
            )?;
        }
        within(
            "filter.ukf.alpha",
            f.ukf.alpha,
            0.0,
            1.000001,
            "must be > 0 and <= 1",
        )?;
        within(
            "filter.ukf.beta",
            f.ukf.beta,
            -f64::MIN_POSITIVE,
            10.0,
            "must be >= 0 and < 10",
        )?;
        if let Some(k) = f.ukf.kappa {
            within("filter.ukf.kappa", k, -100.0, 100.0, "must be within ±100")?;
        }
        for (k, d) in f.model_bank_density_bias.iter().enumerate() {
            within(
                &format!("filter.model_bank_density_bias[{k}]"),
                *d,
                -1.0,
                10.0,
                "must be > -1 and < 10",
            )?;
        }

        if let Some(d) = &f.density {
            d.validate("filter.density")?;
        }

        // Sensors and beacons.
        self.sensors.validate("sensors")?;
        for (name, rate) in [
            (
                "sensors.imu.rate_hz",
                self.sensors.imu.as_ref().map(|s| s.rate_hz),
            ),
            (
                "sensors.dynamic_pressure.rate_hz",
                self.sensors.dynamic_pressure.as_ref().map(|s| s.rate_hz),
            ),
            (
                "sensors.heating.rate_hz",
                self.sensors.heating.as_ref().map(|s| s.rate_hz),
            ),
            (
                "sensors.range.rate_hz",
                self.sensors.range.as_ref().map(|s| s.rate_hz),
            ),
            (
                "sensors.range_rate.rate_hz",
                self.sensors.range_rate.as_ref().map(|s| s.rate_hz),
            ),
        ] {
            if let Some(rate) = rate
                && !is_multiple(1.0 / rate, t.truth_step_s)
            {
                return Err(ScenarioError::range(
                    name,
                    rate,
                    format!(
                        "its period must be an integer multiple of timing.truth_step_s = {}",
                        t.truth_step_s
                    ),
                ));
            }
        }
        let mut names = std::collections::HashSet::new();
        for (i, b) in self.beacons.iter().enumerate() {
            let prefix = format!("beacons[{i}]");
            b.validate(&prefix)?;
            if !names.insert(b.name().to_string()) {
                return Err(ScenarioError::invalid(
                    format!("{prefix}.name"),
                    format!("'{}' is used by two beacons", b.name()),
                ));
            }
            if self.sensors.range.is_some()
                && b.range_sigma_m().is_none()
                && self.sensors.range_rate.is_none()
            {
                return Err(ScenarioError::invalid(
                    format!("{prefix}.range_sigma_m"),
                    "missing: sensors.range is on, so every beacon needs a range noise",
                ));
            }
        }
        if (self.sensors.range.is_some() || self.sensors.range_rate.is_some())
            && self.beacons.is_empty()
        {
            return Err(ScenarioError::invalid(
                "beacons",
                "radio sensors are configured but no beacon is listed",
            ));
        }

        // Dispersions.
        let d = &self.dispersions;
        if let Some(s) = &d.initial {
            s.validate_sigma("dispersions.initial")?;
        }
        within(
            "dispersions.cd_s_over_m_m2kg",
            d.cd_s_over_m_m2kg,
            -f64::MIN_POSITIVE,
            1.0,
            "a 1σ must be >= 0 and < 1",
        )?;
        within(
            "dispersions.lift_to_drag",
            d.lift_to_drag,
            -f64::MIN_POSITIVE,
            3.0,
            "a 1σ must be >= 0 and < 3",
        )?;
        within(
            "dispersions.density_bias",
            d.density_bias,
            -f64::MIN_POSITIVE,
            1.0,
            "a 1σ must be >= 0 and < 1",
        )?;
        within(
            "dispersions.density_bias_clip",
            d.density_bias_clip,
            -f64::MIN_POSITIVE,
            1.0,
            "must be >= 0 (0 = no clipping) and < 1",
        )?;
        if self.monte_carlo.runs == 0 || self.monte_carlo.runs > 1_000_000 {
            return Err(ScenarioError::range(
                "monte_carlo.runs",
                self.monte_carlo.runs,
                "must be >= 1 and <= 1000000",
            ));
        }
        Ok(())
    }
}

/// Range check of the start value of an augmented or consider state.
fn validate_augmented_value(field: &str, a: AugmentedParam, v: f64) -> Result<(), ScenarioError> {
    match a {
        AugmentedParam::Rho0 => within(field, v, 0.0, 1.0, "ρ0 must be > 0 and < 1 kg/m³"),
        AugmentedParam::LiftToDrag => within(field, v, -0.001, 3.0, "L/D must be >= 0 and < 3"),
        AugmentedParam::CdSOverM => within(field, v, 0.0, 1.0, "C_D S/m must be > 0 and < 1 m²/kg"),
        AugmentedParam::DensityBias => within(field, v, -1.0, 10.0, "Δ must be > -1 and < 10"),
        AugmentedParam::AccelBiasX | AugmentedParam::AccelBiasY | AugmentedParam::AccelBiasZ => {
            within(
                field,
                v,
                -10.0,
                10.0,
                "an accelerometer bias must be within ±10 m/s²",
            )
        }
    }
}
