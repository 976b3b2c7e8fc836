//! Checks of `[guidance]`: rate (a multiple of the truth step), reference bank, target,
//! deployment trigger, altitude safeguard floor, bank limits, crossrange corridor and the algorithms' parameters.

use super::config::ScenarioConfig;
use super::error::ScenarioError;
use super::validate::is_multiple;
use super::validate_range::R;
use super::validate_range::{Checker, Range, named};
use crate::guidance::{GuidanceConfig, TargetConfig, Trigger};

/// Largest planet-relative speed a trigger or corridor may name \[m/s\].
const MAX_SPEED_MPS: f64 = 3e4;

impl ScenarioConfig {
    /// `[guidance]`, when present.
    pub(super) fn check_guidance(&self, c: &mut Checker) -> R {
        let Some(g) = &self.guidance else {
            return Ok(());
        };
        c.range(
            "guidance.rate_hz",
            g.rate_hz,
            Range::gt(0.0).le(100.0).unit("Hz"),
        )?;
        let step = self.timing.truth_step_s;
        if !is_multiple(1.0 / g.rate_hz, step) {
            return Err(ScenarioError::range(
                "guidance.rate_hz",
                g.rate_hz,
                format!("its period must be an integer multiple of timing.truth_step_s = {step}"),
            ));
        }
        let angle = || Range::ge(0.0).le(180.0).unit("°");
        c.range("guidance.bank_min_deg", g.bank_min_deg, angle())?;
        let max = Range::ge(named("guidance.bank_min_deg", g.bank_min_deg))
            .le(180.0)
            .unit("°");
        c.range("guidance.bank_max_deg", g.bank_max_deg, max)?;
        let bank = Range::ge(named("guidance.bank_min_deg", g.bank_min_deg))
            .le(named("guidance.bank_max_deg", g.bank_max_deg))
            .unit("°");
        c.range("guidance.reference_bank_deg", g.reference_bank_deg, bank)?;
        let rate = Range::gt(0.0).le(360.0).unit("deg/s");
        c.range(
            "guidance.bank_rate_limit_deg_s",
            g.bank_rate_limit_deg_s,
            rate,
        )?;
        let accel = Range::gt(0.0).le(360.0).unit("deg/s²");
        c.range(
            "guidance.bank_accel_limit_deg_s2",
            g.bank_accel_limit_deg_s2,
            accel,
        )?;
        check_trigger(g, c)?;
        if let Some(h) = g.min_deploy_altitude_m {
            let floor = Range::ge(0.0).le(50_000.0).unit("m");
            c.range("guidance.min_deploy_altitude_m", h, floor)?;
        }
        if let Some(t) = &g.target {
            check_target(t, c)?;
        }
        check_lateral(g, c)?;
        check_algorithms(g, c)
    }
}

fn check_trigger(g: &GuidanceConfig, c: &mut Checker) -> R {
    match g.trigger {
        Trigger::SpeedMps(v) => {
            let range = Range::gt(0.0).lt(MAX_SPEED_MPS).unit("m/s");
            c.range("guidance.trigger.speed_mps", v, range)
        }
        Trigger::DynamicPressurePa(q) => {
            let range = Range::gt(0.0).le(1e6).unit("Pa");
            c.range("guidance.trigger.dynamic_pressure_pa", q, range)
        }
        Trigger::Range(rt) => {
            let range = Range::gt(0.0).lt(MAX_SPEED_MPS).unit("m/s");
            c.range(
                "guidance.trigger.range.nominal_speed_mps",
                rt.nominal_speed_mps,
                range,
            )?;
            let backstop = Range::gt(0.0)
                .le(named(
                    "guidance.trigger.range.nominal_speed_mps",
                    rt.nominal_speed_mps,
                ))
                .unit("m/s");
            c.range(
                "guidance.trigger.range.backstop_speed_mps",
                rt.backstop_speed_mps,
                backstop,
            )?;
            let margin = Range::ge(0.0).le(0.5);
            c.range(
                "guidance.trigger.range.window_margin",
                rt.window_margin,
                margin,
            )
        }
    }?;
    check_box(g, c)
}

fn check_box(g: &GuidanceConfig, c: &mut Checker) -> R {
    let b = &g.deploy_box;
    let vmin = Range::ge(0.0).lt(MAX_SPEED_MPS).unit("m/s");
    c.range("guidance.deploy_box.speed_min_mps", b.speed_min_mps, vmin)?;
    let vmax = Range::gt(named("guidance.deploy_box.speed_min_mps", b.speed_min_mps))
        .lt(MAX_SPEED_MPS)
        .unit("m/s");
    c.range("guidance.deploy_box.speed_max_mps", b.speed_max_mps, vmax)?;
    let qmin = Range::ge(0.0).lt(1e6).unit("Pa");
    let qmin_v = b.dynamic_pressure_min_pa;
    c.range("guidance.deploy_box.dynamic_pressure_min_pa", qmin_v, qmin)?;
    let qmax = Range::gt(named("guidance.deploy_box.dynamic_pressure_min_pa", qmin_v))
        .le(1e6)
        .unit("Pa");
    let qmax_v = b.dynamic_pressure_max_pa;
    c.range("guidance.deploy_box.dynamic_pressure_max_pa", qmax_v, qmax)?;
    let h = Range::ge(-1e4).le(1e5).unit("m");
    c.range("guidance.deploy_box.altitude_min_m", b.altitude_min_m, h)
}

fn check_target(t: &TargetConfig, c: &mut Checker) -> R {
    match (t.lat_deg, t.lon_deg, t.range_km) {
        (Some(lat), Some(lon), None) => {
            c.range(
                "guidance.target.lat_deg",
                lat,
                Range::within(90.0).unit("°"),
            )?;
            c.range(
                "guidance.target.lon_deg",
                lon,
                Range::within(360.0).unit("°"),
            )
        }
        (None, None, Some(km)) => {
            // Less than half a circumference of Mars (π · 3396.2 km).
            let range = Range::gt(0.0).lt(10000.0).unit("km");
            c.range("guidance.target.range_km", km, range)
        }
        _ => Err(ScenarioError::invalid(
            "guidance.target",
            "give either lat_deg and lon_deg, or range_km",
        )),
    }
}

fn check_lateral(g: &GuidanceConfig, c: &mut Checker) -> R {
    let l = &g.lateral;
    let high = Range::ge(0.0).le(1e6).unit("m");
    c.range("guidance.lateral.deadband_high_m", l.deadband_high_m, high)?;
    let low = Range::ge(0.0)
        .le(named("guidance.lateral.deadband_high_m", l.deadband_high_m))
        .unit("m");
    c.range("guidance.lateral.deadband_low_m", l.deadband_low_m, low)?;
    let vh = Range::gt(0.0).lt(MAX_SPEED_MPS).unit("m/s");
    c.range("guidance.lateral.speed_high_mps", l.speed_high_mps, vh)?;
    let vl = Range::ge(0.0)
        .lt(named("guidance.lateral.speed_high_mps", l.speed_high_mps))
        .unit("m/s");
    c.range("guidance.lateral.speed_low_mps", l.speed_low_mps, vl)
}

fn check_algorithms(g: &GuidanceConfig, c: &mut Checker) -> R {
    let speed = || Range::ge(0.0).lt(MAX_SPEED_MPS).unit("m/s");
    let a = &g.apollo;
    let gain = Range::gt(0.0).le(100.0);
    c.range("guidance.apollo.overcontrol_gain", a.overcontrol_gain, gain)?;
    let drag = Range::ge(0.0).le(1000.0).unit("m/s²");
    c.range("guidance.apollo.start_drag_mps2", a.start_drag_mps2, drag)?;
    c.range("guidance.apollo.hold_speed_mps", a.hold_speed_mps, speed())?;
    if let Some(v) = a.heading_alignment_speed_mps {
        let vh = Range::gt(0.0).lt(MAX_SPEED_MPS).unit("m/s");
        c.range("guidance.apollo.heading_alignment_speed_mps", v, vh)?;
    }
    let k = Range::gt(0.0).le(1000.0);
    c.range(
        "guidance.apollo.heading_alignment_gain",
        a.heading_alignment_gain,
        k,
    )?;
    let ha_bank = Range::gt(0.0).le(180.0).unit("°");
    let b = a.heading_alignment_max_bank_deg;
    c.range("guidance.apollo.heading_alignment_max_bank_deg", b, ha_bank)?;
    let f = &g.fnpeg;
    let bank = Range::ge(named("guidance.bank_min_deg", g.bank_min_deg))
        .le(named("guidance.bank_max_deg", g.bank_max_deg))
        .unit("°");
    c.range("guidance.fnpeg.final_bank_deg", f.final_bank_deg, bank)?;
    let step = Range::gt(0.0).le(10.0).unit("s");
    c.range("guidance.fnpeg.predictor_step_s", f.predictor_step_s, step)?;
    let iterations = Range::ge(1.0).le(50.0);
    c.range("guidance.fnpeg.iterations", f.iterations, iterations)?;
    let beta = Range::ge(0.0)
        .le(1.0)
        .note("0 = trust the onboard atmosphere");
    c.range("guidance.fnpeg.density_gain", f.density_gain, beta)?;
    c.range("guidance.fnpeg.hold_speed_mps", f.hold_speed_mps, speed())
}
