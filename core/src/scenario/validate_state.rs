//! Range checks of the states and vehicles a scenario gives (`truth.initial`, `filter.initial`,
//! `dispersions.initial`, `truth.vehicle`, `filter.vehicle`) and which form a state has.

use super::config::{StateConfig, VehicleConfig};
use super::error::ScenarioError;
use super::validate_range::{Checker, R, Range, named};
use crate::planet::Planet;

/// Which complete form a [`StateConfig`] has.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum StateForm {
    /// radius/lon/lat/speed/fpa/heading.
    Spherical,
    /// position/velocity.
    Cartesian,
}

/// Largest entry speed \[m/s\].
const MAX_SPEED_MPS: f64 = 3e4;

/// Largest 1σ of a dispersed state component (km, degrees or m/s).
const MAX_STATE_SIGMA: f64 = 1e4;

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

    /// Check a state of the vehicle (`truth.initial`, `filter.initial`) above `planet`.
    pub(super) fn check_state(&self, field: &str, planet: &Planet, c: &mut Checker) -> R {
        let r_km = planet.radius / 1e3;
        let radius =
            || Range::gt(named("the surface", r_km)).lt(named("10 planet radii", 10.0 * r_km));
        let speed = || Range::gt(0.0).lt(MAX_SPEED_MPS).unit("m/s");
        let f = |name: &str| format!("{field}.{name}");
        match self.form(field)? {
            StateForm::Spherical => {
                let [r, lat, lon, v, fpa, heading] = [
                    self.radius_km,
                    self.lat_deg,
                    self.lon_deg,
                    self.speed_mps,
                    self.fpa_deg,
                    self.heading_deg,
                ]
                .map(Option::unwrap_or_default);
                c.range(f("radius_km"), r, radius().unit("km"))?;
                c.range(f("lat_deg"), lat, Range::strictly_within(90.0).unit("°"))?;
                c.range(f("lon_deg"), lon, Range::within(360.0).unit("°"))?;
                c.range(f("speed_mps"), v, speed())?;
                c.range(f("fpa_deg"), fpa, Range::strictly_within(90.0).unit("°"))?;
                c.range(f("heading_deg"), heading, Range::within(360.0).unit("°"))
            }
            StateForm::Cartesian => {
                let norm = |v: [f64; 3]| (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                let p = norm(self.position_km.unwrap_or_default());
                let v = norm(self.velocity_mps.unwrap_or_default());
                c.range(f("position_km"), p, radius().unit("km").of("its norm"))?;
                c.range(f("velocity_mps"), v, speed().of("its norm"))
            }
        }
    }

    /// Check the 1σ dispersions of a state (`dispersions.initial`): every given component.
    pub(super) fn check_sigma(&self, field: &str, c: &mut Checker) -> R {
        let sigma = || Range::ge(0.0).lt(MAX_STATE_SIGMA).of("a 1σ");
        let scalars = [
            ("radius_km", self.radius_km),
            ("lon_deg", self.lon_deg),
            ("lat_deg", self.lat_deg),
            ("speed_mps", self.speed_mps),
            ("fpa_deg", self.fpa_deg),
            ("heading_deg", self.heading_deg),
        ];
        for (name, v) in scalars {
            if let Some(v) = v {
                c.range(format!("{field}.{name}"), v, sigma())?;
            }
        }
        let vectors = [
            ("position_km", self.position_km),
            ("velocity_mps", self.velocity_mps),
        ];
        for (name, v) in vectors {
            for (k, x) in v.iter().flatten().enumerate() {
                c.range(format!("{field}.{name}[{k}]"), *x, sigma())?;
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

    /// Check a vehicle (`truth.vehicle`, `filter.vehicle`): one way of giving the drag, L/D.
    pub(super) fn check(&self, field: &str, c: &mut Checker) -> R {
        let f = |name: &str| format!("{field}.{name}");
        match (self.cd_s_over_m_m2kg, self.ballistic_coefficient_kgm2) {
            (Some(b), None) => c.range(f("cd_s_over_m_m2kg"), b, cd_s_over_m_range())?,
            (None, Some(beta)) => c.range(
                f("ballistic_coefficient_kgm2"),
                beta,
                Range::gt(0.0)
                    .lt(1e5)
                    .unit("kg/m²")
                    .note("mass and area positive"),
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
        c.range(f("lift_to_drag"), self.lift_to_drag, lift_to_drag_range())
    }
}

/// Allowed C_D S/m \[m²/kg\] (also of an augmented start value).
pub(super) fn cd_s_over_m_range() -> Range {
    Range::gt(0.0)
        .lt(1.0)
        .unit("m²/kg")
        .note("mass and area positive")
}

/// Allowed lift-to-drag ratios (also of an augmented start value).
pub(super) fn lift_to_drag_range() -> Range {
    Range::ge(0.0).lt(3.0)
}
