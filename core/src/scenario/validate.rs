//! Validation of a [`ScenarioConfig`], section by section; every error names field, value and
//! range. Numeric ranges go through the one [`Range`] check, which writes its own message; the
//! sections live in `validate_state` (states, vehicles), `validate_filter` (`[filter]`) and
//! `validate_density` (`[filter.density]`).

use super::config::*;
use super::error::ScenarioError;
pub use super::validate_filter::MAX_UPDATE_ITERATIONS;
use super::validate_filter::density_bias_range;
use super::validate_range::R;
pub use super::validate_range::{Checker, Limit, Range, RangeCheck, named};
pub use super::validate_state::StateForm;
use crate::planet::Planet;

/// Longest `timing.truth_step_s` \[s\] (and never longer than the run).
const MAX_TRUTH_STEP_S: f64 = 10.0;

/// Most truth steps one run may take (`timing.duration_s / timing.truth_step_s`): the work a
/// scenario implies is bounded before a run starts (the built-ins take 2400–7000). A million
/// RK4 steps of the truth are a few seconds per run.
pub const MAX_TRUTH_STEPS: f64 = 1e6;

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

    fn check(&self, c: &mut Checker) -> R {
        if let Some(mu) = self.mu_m3s2 {
            let range = Range::gt(1e9).lt(1e17).unit("m³/s²");
            c.range("planet.mu_m3s2", mu, range)?;
        }
        if let Some(r) = self.radius_km {
            c.range("planet.radius_km", r, Range::gt(100.0).lt(1e5).unit("km"))?;
        }
        if let Some(w) = self.rotation_rate_rad_s {
            let range = Range::within(1e-3).unit("rad/s");
            c.range("planet.rotation_rate_rad_s", w, range)?;
        }
        Ok(())
    }
}

impl TimingConfig {
    fn check(&self, c: &mut Checker) -> R {
        let duration = Range::gt(0.0).le(7200.0).unit("s");
        c.range("timing.duration_s", self.duration_s, duration)?;
        let step = self.truth_step_s;
        let shortest = named("timing.duration_s / 1e6", self.duration_s / MAX_TRUTH_STEPS);
        let range = Range::ge(shortest)
            .unit("s")
            .note("at most 1e6 truth steps per run");
        let range = if self.duration_s < MAX_TRUTH_STEP_S {
            range.le(named("timing.duration_s", self.duration_s))
        } else {
            range.le(MAX_TRUTH_STEP_S)
        };
        c.range("timing.truth_step_s", step, range)?;
        let filter_step = Range::gt(0.0).le(60.0).unit("s");
        c.range("timing.filter_step_s", self.filter_step_s, filter_step)?;
        if !is_multiple(self.filter_step_s, step) {
            return Err(ScenarioError::range(
                "timing.filter_step_s",
                self.filter_step_s,
                format!("must be an integer multiple of timing.truth_step_s = {step}"),
            ));
        }
        if let Some(s) = self.stop_speed_mps {
            let range = Range::gt(0.0).lt(3e4).unit("m/s");
            c.range("timing.stop_speed_mps", s, range)?;
        }
        Ok(())
    }
}

impl ScenarioConfig {
    /// Check every field; the first problem found is returned.
    pub fn validate(&self) -> R {
        self.check(&mut Checker::new())?;
        self.refuse_implausible()
    }

    /// The first implausible initial-state value ([`ScenarioConfig::implausible`]) as an error,
    /// unless `allow_implausible` is set.
    pub fn refuse_implausible(&self) -> R {
        match self.implausible().into_iter().next() {
            Some(w) if !self.allow_implausible => Err(ScenarioError::Implausible(w)),
            _ => Ok(()),
        }
    }

    /// Validate as [`ScenarioConfig::validate`] does and list every range check made, in order
    /// (which ranges apply depends on the sections present).
    pub fn range_checks(&self) -> Result<Vec<RangeCheck>, ScenarioError> {
        let mut c = Checker::listing();
        self.check(&mut c)?;
        Ok(c.into_checks())
    }

    fn check(&self, c: &mut Checker) -> R {
        if self.name.trim().is_empty() {
            return Err(ScenarioError::invalid("name", "must not be empty"));
        }
        self.planet.check(c)?;
        let planet = self.planet.resolve();
        self.timing.check(c)?;
        self.check_truth(&planet, c)?;
        self.check_filter(&planet, c)?;
        self.check_sensors()?;
        self.check_beacons()?;
        self.check_dispersions(c)?;
        self.check_faults(c)?;
        self.check_guidance(c)?;
        let runs = Range::ge(1.0).le(1e6);
        c.range("monte_carlo.runs", self.monte_carlo.runs, runs)
    }

    /// `[truth]`: initial state, vehicle, atmosphere and its perturbation, bias, bank.
    fn check_truth(&self, planet: &Planet, c: &mut Checker) -> R {
        let t = &self.truth;
        t.initial.check_state("truth.initial", planet, c)?;
        t.vehicle.check("truth.vehicle", c)?;
        t.atmosphere.validate("truth.atmosphere")?;
        if let Some(p) = &t.perturbation {
            p.validate("truth.perturbation")?;
        }
        c.range("truth.density_bias", t.density_bias, density_bias_range())?;
        c.range("truth.bank_deg", t.bank_deg, Range::within(180.0).unit("°"))
    }

    /// `[sensors]`: each sensor's own checks, and every period a multiple of the truth step.
    fn check_sensors(&self) -> R {
        let s = &self.sensors;
        s.validate("sensors")?;
        let step = self.timing.truth_step_s;
        let rates = [
            ("imu", s.imu.as_ref().map(|s| s.rate_hz)),
            (
                "dynamic_pressure",
                s.dynamic_pressure.as_ref().map(|s| s.rate_hz),
            ),
            ("heating", s.heating.as_ref().map(|s| s.rate_hz)),
            ("range", s.range.as_ref().map(|s| s.rate_hz)),
            ("range_rate", s.range_rate.as_ref().map(|s| s.rate_hz)),
        ];
        for (name, rate) in rates {
            if let Some(rate) = rate
                && !is_multiple(1.0 / rate, step)
            {
                return Err(ScenarioError::range(
                    format!("sensors.{name}.rate_hz"),
                    rate,
                    format!(
                        "its period must be an integer multiple of timing.truth_step_s = {step}"
                    ),
                ));
            }
        }
        Ok(())
    }

    /// `[[beacons]]`: each beacon's own checks, unique names, the noise the radios need.
    fn check_beacons(&self) -> R {
        let mut names = std::collections::HashSet::new();
        let radio = self.sensors.range.is_some() || self.sensors.range_rate.is_some();
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
        if radio && self.beacons.is_empty() {
            return Err(ScenarioError::invalid(
                "beacons",
                "radio sensors are configured but no beacon is listed",
            ));
        }
        Ok(())
    }

    /// `[dispersions]`: 1σ of the initial state, the vehicle and the density bias.
    fn check_dispersions(&self, c: &mut Checker) -> R {
        let d = &self.dispersions;
        if let Some(s) = &d.initial {
            s.check_sigma("dispersions.initial", c)?;
        }
        let sigma = |hi: f64| Range::ge(0.0).lt(hi).of("a 1σ");
        c.range(
            "dispersions.cd_s_over_m_m2kg",
            d.cd_s_over_m_m2kg,
            sigma(1.0),
        )?;
        c.range("dispersions.lift_to_drag", d.lift_to_drag, sigma(3.0))?;
        c.range("dispersions.density_bias", d.density_bias, sigma(1.0))?;
        let clip = Range::ge(0.0).lt(1.0).note("0 = no clipping");
        c.range("dispersions.density_bias_clip", d.density_bias_clip, clip)
    }
}
