//! Where a flight deployed: the [`Delivery`] (point, miss to the target, largest bank rate, the
//! navigation error there), the trigger function on a truth sample and the deployment point
//! between the two truth samples around its crossing.

use super::guided_flight::GuidedFlight;
use crate::guidance::{
    BankLimits, BoxViolations, DeployBox, Target, Trigger, bearing, central_angle,
};
use crate::sim::engine::TruthSample;
use serde::{Deserialize, Serialize};

/// The navigation error at deployment: the filter's latest estimate (the last measurement epoch
/// at or before the trigger) against the truth at that epoch.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct DeployNavError {
    /// Position error norm \[m\].
    pub position_m: f64,
    /// Velocity error norm \[m/s\].
    pub velocity_mps: f64,
    /// Downrange (along the true heading) position error \[m\].
    pub downrange_m: f64,
    /// Crossrange position error \[m\].
    pub crossrange_m: f64,
    /// NEES of the six kinematic states there, eᵀP⁻¹e with the filter's own covariance (χ² with
    /// 6 degrees of freedom for a consistent filter); `None` where it is not defined. Absent in
    /// shards written before it was recorded.
    #[serde(default)]
    pub nees_kinematic: Option<f64>,
}

/// Where one flight deployed and how far from the target.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub struct Delivery {
    /// Deployment time \[s\].
    pub t_deploy_s: f64,
    /// Deployment latitude \[deg\].
    pub lat_deg: f64,
    /// Deployment longitude \[deg\].
    pub lon_deg: f64,
    /// Deployment altitude \[m\].
    pub altitude_m: f64,
    /// Planet-relative speed at deployment \[m/s\] (0 in shards written before it was recorded).
    #[serde(default)]
    pub speed_mps: f64,
    /// True dynamic pressure at deployment \[Pa\] (0 in shards written before it was recorded).
    #[serde(default)]
    pub dynamic_pressure_pa: f64,
    /// The limits of the deployment box (`guidance.deploy_box`) the true conditions at
    /// deployment broke (none: deployed inside the box).
    #[serde(default)]
    pub outside_box: BoxViolations,
    /// Surface distance from the deployment point to the target \[m\].
    pub miss_m: f64,
    /// Along-track part of the miss, positive when the vehicle overflew the target \[m\].
    pub downrange_m: f64,
    /// Cross-track part of the miss, positive when the target lies to the right \[m\].
    pub crossrange_m: f64,
    /// Largest |bank rate| flown over any truth step \[deg/s\].
    pub max_bank_rate_deg_s: f64,
    /// Navigation error at deployment (`None` for perfect navigation and the unguided flight).
    pub nav_error: Option<DeployNavError>,
}

impl Delivery {
    /// The delivery of a flight of [`super::guided_flight`] (perfect navigation or a constant
    /// bank), with the largest bank rate over its samples, judged against `deploy_box`.
    pub fn from_flight(f: &GuidedFlight, deploy_box: &DeployBox) -> Delivery {
        let max_rate = f
            .samples
            .windows(2)
            .map(|w| (w[1].bank - w[0].bank).abs() / (w[1].t - w[0].t))
            .fold(0.0, f64::max);
        Delivery {
            t_deploy_s: f.t_deploy,
            lat_deg: f.deploy_lat_lon[0].to_degrees(),
            lon_deg: f.deploy_lat_lon[1].to_degrees(),
            altitude_m: f.deploy_altitude_m,
            speed_mps: f.deploy_speed_mps,
            dynamic_pressure_pa: f.deploy_dynamic_pressure_pa,
            outside_box: deploy_box.check(
                f.deploy_altitude_m,
                f.deploy_speed_mps,
                f.deploy_dynamic_pressure_pa,
            ),
            miss_m: f.miss_m,
            downrange_m: f.downrange_error_m,
            crossrange_m: f.crossrange_error_m,
            max_bank_rate_deg_s: max_rate.to_degrees(),
            nav_error: None,
        }
    }
}

/// The trigger function on a truth sample (airspeed from the dynamic pressure, so it is the
/// planet-relative air speed on a rotating planet too).
pub(super) fn trigger_on(trigger: &Trigger, s: &TruthSample) -> f64 {
    let airspeed = if s.density > 0.0 {
        (2.0 * s.dynamic_pressure / s.density).sqrt()
    } else {
        s.spherical[3]
    };
    trigger.function(s.density, airspeed)
}

/// The deployment point between the truth samples `prev` (trigger `c_prev > 0`) and `s`
/// (`c ≤ 0`), and its miss to `target` on a sphere of `radius`, judged against `deploy_box`.
pub(super) fn deployment(
    (prev, s): (&TruthSample, &TruthSample),
    (c_prev, c): (f64, f64),
    target: &Target,
    radius: f64,
    deploy_box: &DeployBox,
) -> Delivery {
    let w = c_prev / (c_prev - c);
    let lerp = |i: usize| prev.spherical[i] + w * (s.spherical[i] - prev.spherical[i]);
    let (lat, lon, psi) = (lerp(2), lerp(1), lerp(5));
    let altitude = lerp(0) - radius;
    let q = prev.dynamic_pressure + w * (s.dynamic_pressure - prev.dynamic_pressure);
    let dist = central_angle(lat, lon, target.lat, target.lon);
    let b = bearing(lat, lon, target.lat, target.lon);
    Delivery {
        t_deploy_s: prev.t + w * (s.t - prev.t),
        lat_deg: lat.to_degrees(),
        lon_deg: lon.to_degrees(),
        altitude_m: altitude,
        speed_mps: lerp(3),
        dynamic_pressure_pa: q,
        outside_box: deploy_box.check(altitude, lerp(3), q),
        miss_m: radius * dist,
        downrange_m: -radius * dist * (b - psi).cos(),
        crossrange_m: radius * (dist.sin() * (b - psi).sin()).asin(),
        max_bank_rate_deg_s: 0.0,
        nav_error: None,
    }
}

/// Whether every bank rate of a delivery stayed within `limits` (relative tolerance 1e-9).
pub fn within_rate_limit(d: &Delivery, limits: &BankLimits) -> bool {
    d.max_bank_rate_deg_s <= limits.rate_max.to_degrees() * (1.0 + 1e-9)
}
