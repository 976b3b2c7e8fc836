//! Parachute deployment: the box a deployment must meet, and the range trigger's onboard decision.
//!
//! **The box** (`[guidance.deploy_box]`): the conditions a supersonic parachute can be deployed in
//! — a speed (Mach) window, a dynamic-pressure window and an altitude floor. Every trigger is
//! judged against it at deployment (on the truth: the parachute meets the real air); a
//! deployment outside it still counts as deployed (its miss stays in the statistics) and is
//! reported apart, by broken limit (`guidance deliver`'s `in box` column, `outside_box_by_limit`
//! and a warning). The defaults are our choice: a
//! 5 km altitude floor (the issue's acceptance), 250–850 Pa and 380–540 m/s (our reading of the
//! disk-gap-band parachute envelope MSL and Mars 2020 flew, about Mach 1.1–2.3 and 250–850 Pa,
//! with the speed of sound near 230–240 m/s at 5–12 km on Mars; we have not checked these numbers
//! against a qualification document and do not model Mach).
//!
//! **The range trigger** (Mars 2020; Dutta & Way, *Comparison of the effects of velocity and
//! range triggers on trajectory dispersions for the Mars 2020 mission*, AIAA SciTech 2017, NASA
//! NTRS 20170000743, and Way et al. on Mars 2020's flown entry): the parachute is deployed when the onboard range-to-go to the target reaches zero,
//! provided the vehicle is inside the speed and dynamic-pressure window (a vehicle that arrives
//! fast waits for the window and overflies the target), and at the backstop speed when the
//! range-to-go has not reached zero by then (a short vehicle deploys short). As a single trigger
//! function, positive before deployment:
//!
//! ```text
//! c = min( max(R_togo, v − (1 − m)·v_max, q − (1 − m)·q_max), v − v_backstop )
//! ```
//!
//! R_togo \[m\] the along-track range to the target (negative past it), v \[m/s\] and q \[Pa\]
//! the onboard speed and dynamic pressure, m the window's margin inside the box (1 %, our
//! choice: with none, 3 of 1000 FNPEG runs with USKF-NN in the loop that waited at the window's
//! edge deployed 0.1 Pa above the box); the terms mix units, which only matters for where
//! between two samples the zero is interpolated (within one step). Onboard predictions (the
//! reference trajectory, FNPEG, the safeguard) end at the trigger's `nominal_speed_mps`.

use super::nav_state::NavState;
use super::target::{Target, bearing, central_angle};
use serde::{Deserialize, Serialize};

/// The Mars 2020 range trigger: deploy where the onboard range-to-go to the target reaches zero
/// inside the deployment box's speed and pressure window, or at the backstop speed.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RangeTrigger {
    /// The speed every onboard prediction ends at, the reference trajectory's deployment and so
    /// the default target's \[m/s\].
    pub nominal_speed_mps: f64,
    /// Deploy at this speed when the range-to-go has not reached zero \[m/s\].
    pub backstop_speed_mps: f64,
    /// The fraction by which the trigger's window keeps clear of the box's speed and pressure
    /// maxima: it waits for v ≤ (1 − m)·v_max and q ≤ (1 − m)·q_max, so that a vehicle waiting
    /// at the window's edge is not deployed outside the box by the onboard speed and pressure's
    /// errors (default [`RangeTrigger::DEFAULT_WINDOW_MARGIN`], our choice: 8.5 Pa and 5.4 m/s
    /// on the default box; 0 puts the window on the box).
    #[serde(default = "default_window_margin")]
    pub window_margin: f64,
}

fn default_window_margin() -> f64 {
    RangeTrigger::DEFAULT_WINDOW_MARGIN
}

/// The deployment box (`[guidance.deploy_box]`, module documentation).
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct DeployBox {
    /// Lowest planet-relative speed at deployment \[m/s\].
    pub speed_min_mps: f64,
    /// Highest planet-relative speed at deployment \[m/s\] (the range trigger waits below it).
    pub speed_max_mps: f64,
    /// Lowest dynamic pressure at deployment \[Pa\].
    pub dynamic_pressure_min_pa: f64,
    /// Highest dynamic pressure at deployment \[Pa\] (the range trigger waits below it).
    pub dynamic_pressure_max_pa: f64,
    /// Lowest altitude at deployment \[m\].
    pub altitude_min_m: f64,
}

impl Default for DeployBox {
    fn default() -> Self {
        DeployBox {
            speed_min_mps: 380.0,
            speed_max_mps: 540.0,
            dynamic_pressure_min_pa: 250.0,
            dynamic_pressure_max_pa: 850.0,
            altitude_min_m: 5000.0,
        }
    }
}

/// Which limits of the [`DeployBox`] a deployment broke (all `false`: inside).
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize)]
#[serde(default)]
pub struct BoxViolations {
    /// Below `altitude_min_m`.
    pub altitude_low: bool,
    /// Below `speed_min_mps`.
    pub speed_low: bool,
    /// Above `speed_max_mps`.
    pub speed_high: bool,
    /// Below `dynamic_pressure_min_pa`.
    pub pressure_low: bool,
    /// Above `dynamic_pressure_max_pa`.
    pub pressure_high: bool,
}

impl BoxViolations {
    /// Whether any limit was broken.
    pub fn any(&self) -> bool {
        !self.names().is_empty()
    }

    /// The broken limits in words ("altitude below the floor", …), in a fixed order.
    pub fn names(&self) -> Vec<&'static str> {
        [
            (self.altitude_low, "altitude below the floor"),
            (self.speed_low, "speed below the box"),
            (self.speed_high, "speed above the box"),
            (self.pressure_low, "dynamic pressure below the box"),
            (self.pressure_high, "dynamic pressure above the box"),
        ]
        .into_iter()
        .filter_map(|(b, n)| b.then_some(n))
        .collect()
    }
}

impl DeployBox {
    /// The limits a deployment at `altitude_m`, `speed_mps` and `dynamic_pressure_pa` breaks.
    pub fn check(
        &self,
        altitude_m: f64,
        speed_mps: f64,
        dynamic_pressure_pa: f64,
    ) -> BoxViolations {
        BoxViolations {
            // A NaN breaks every limit it is compared with.
            altitude_low: altitude_m.is_nan() || altitude_m < self.altitude_min_m,
            speed_low: speed_mps.is_nan() || speed_mps < self.speed_min_mps,
            speed_high: speed_mps.is_nan() || speed_mps > self.speed_max_mps,
            pressure_low: dynamic_pressure_pa.is_nan()
                || dynamic_pressure_pa < self.dynamic_pressure_min_pa,
            pressure_high: dynamic_pressure_pa.is_nan()
                || dynamic_pressure_pa > self.dynamic_pressure_max_pa,
        }
    }
}

/// The signed along-track range-to-go \[m\] from `nav` to `target` on a sphere of `radius`:
/// positive while the target lies ahead along the heading, negative past it.
pub fn along_track_range_to_go(nav: &NavState, target: &Target, radius: f64) -> f64 {
    let [_, lon, lat, _, _, psi] = nav.spherical;
    let d = central_angle(lat, lon, target.lat, target.lon);
    let b = bearing(lat, lon, target.lat, target.lon);
    radius * d * (b - psi).cos()
}

impl RangeTrigger {
    /// The default [`RangeTrigger::window_margin`]: 1 %.
    pub const DEFAULT_WINDOW_MARGIN: f64 = 0.01;

    /// The range trigger function (module documentation) at along-track range-to-go `range_m`,
    /// speed `speed_mps` and dynamic pressure `dynamic_pressure_pa`: positive before deployment.
    pub fn function(
        &self,
        window: &DeployBox,
        range_m: f64,
        speed_mps: f64,
        dynamic_pressure_pa: f64,
    ) -> f64 {
        let keep = 1.0 - self.window_margin;
        let at_target = range_m
            .max(speed_mps - keep * window.speed_max_mps)
            .max(dynamic_pressure_pa - keep * window.dynamic_pressure_max_pa);
        at_target.min(speed_mps - self.backstop_speed_mps)
    }

    /// The range trigger function on the onboard view: the navigation solution `nav` (at its
    /// epoch `nav.t`) carried forward to time `t` to first order (range-to-go by −v cosγ Δt,
    /// speed by −(D + g sinγ) Δt, g = μ/r²), the dynamic pressure from the sensed drag and the
    /// onboard ballistic coefficient, q = D / (C_D S/m). Only onboard quantities.
    pub fn on_estimate(
        &self,
        window: &DeployBox,
        nav: &NavState,
        t: f64,
        onboard: &OnboardDeploy,
    ) -> f64 {
        let dt = (t - nav.t).max(0.0);
        let [r, _, _, v, fpa, _] = nav.spherical;
        let g = onboard.mu / (r * r);
        let range =
            along_track_range_to_go(nav, &onboard.target, onboard.radius) - v * fpa.cos() * dt;
        let speed = v - (nav.drag_mps2 + g * fpa.sin()) * dt;
        let q = if onboard.cd_s_over_m > 0.0 {
            nav.drag_mps2 / onboard.cd_s_over_m
        } else {
            0.0
        };
        self.function(window, range, speed, q)
    }
}

/// The onboard constants the range trigger needs beside the navigation solution.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct OnboardDeploy {
    /// The target.
    pub target: Target,
    /// Planet radius for arc lengths \[m\].
    pub radius: f64,
    /// Gravitational parameter μ \[m³/s²\].
    pub mu: f64,
    /// Onboard C_D S/m \[m²/kg\].
    pub cd_s_over_m: f64,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_range_trigger_waits_for_the_window_and_has_a_backstop() {
        let rt = RangeTrigger {
            nominal_speed_mps: 450.0,
            backstop_speed_mps: 400.0,
            window_margin: 0.0,
        };
        let b = DeployBox::default();
        // Target ahead, fast: not yet.
        assert!(rt.function(&b, 1000.0, 500.0, 600.0) > 0.0);
        // At the target inside the window: deploy.
        assert!(rt.function(&b, -1.0, 500.0, 600.0) <= 0.0);
        // Past the target but above the window's speed or pressure: wait.
        assert!(rt.function(&b, -5000.0, 600.0, 600.0) > 0.0);
        assert!(rt.function(&b, -5000.0, 500.0, 900.0) > 0.0);
        // Short of the target at the backstop: deploy.
        assert!(rt.function(&b, 5000.0, 399.0, 600.0) <= 0.0);
    }

    #[test]
    fn the_window_margin_keeps_the_trigger_inside_the_box() {
        let b = DeployBox::default();
        let with = |window_margin| RangeTrigger {
            nominal_speed_mps: 450.0,
            backstop_speed_mps: 400.0,
            window_margin,
        };
        // Past the target at 845 Pa: on the box's edge it deploys, 1 % inside it (841.5 Pa) waits.
        assert!(with(0.0).function(&b, -100.0, 450.0, 845.0) <= 0.0);
        assert!(with(0.01).function(&b, -100.0, 450.0, 845.0) > 0.0);
        assert!(with(0.01).function(&b, -100.0, 450.0, 841.0) <= 0.0);
        // The same on speed: 540 m/s box, 534.6 m/s window.
        assert!(with(0.01).function(&b, -100.0, 536.0, 600.0) > 0.0);
        assert!(with(0.01).function(&b, -100.0, 534.0, 600.0) <= 0.0);
        // A scenario that does not name it gets the default.
        let rt: RangeTrigger =
            toml::from_str("nominal_speed_mps = 450.0\nbackstop_speed_mps = 400.0").unwrap();
        assert_eq!(rt.window_margin, RangeTrigger::DEFAULT_WINDOW_MARGIN);
    }

    #[test]
    fn the_box_names_what_it_broke() {
        let b = DeployBox::default();
        assert!(!b.check(9000.0, 450.0, 500.0).any());
        let v = b.check(4000.0, 450.0, 900.0);
        assert_eq!(
            v.names(),
            ["altitude below the floor", "dynamic pressure above the box"]
        );
        assert!(b.check(f64::NAN, 450.0, 500.0).altitude_low);
    }
}
