//! Cartesian inertial entry dynamics with aerodynamics in the wind frame (seed 003 §1).

use super::aero::{AeroParams, drag_lift, wind_frame};
use crate::atmosphere::Atmosphere;
use crate::math::{Real, V3, cross, norm, sub};
use crate::planet::Planet;

/// Time derivative of the inertial state `[x, y, z, vx, vy, vz]`, seed 003 eq. 1–5:
///
/// ```text
/// v_rel = v − Ω × r                                   (eq. 1, atmosphere at rest w.r.t. the surface)
/// ṙ = v
/// v̇ = −D w_x − L sinσ w_y + L cosσ w_z − g r/‖r‖       (eq. 3)
/// D = ½ ρ ‖v_rel‖² / (m/(C_D S)),  L = (L/D)·D         (eq. 4)
/// ```
///
/// with the wind frame of [`wind_frame`] (eq. 1–2), g = μ/‖r‖² and ρ = `density_scale`·ρ_model(‖r‖ − R).
pub fn cartesian_rhs<T: Real, A: Atmosphere>(
    x: &[T; 6],
    aero: &AeroParams<T>,
    atmosphere: &A,
    planet: &Planet,
    omega: f64,
) -> [T; 6] {
    let r: V3<T> = [x[0], x[1], x[2]];
    let v: V3<T> = [x[3], x[4], x[5]];
    let rn = norm(&r);
    let w = [T::from(0.0), T::from(0.0), T::from(omega)];
    let v_rel = sub(&v, &cross(&w, &r));
    let speed = norm(&v_rel);
    let rho = atmosphere.density(rn - planet.radius) * aero.density_scale;
    let (d, l) = drag_lift(rho, speed, aero);
    let [wx, wy, wz] = wind_frame(&r, &v_rel);
    let (sb, cb) = (aero.bank.sin(), aero.bank.cos());
    let g_over_r = (rn * rn * rn).recip() * planet.mu;
    let mut a = [T::from(0.0); 3];
    for k in 0..3 {
        a[k] = -(d * wx[k]) - l * sb * wy[k] + l * cb * wz[k] - g_over_r * r[k];
    }
    [v[0], v[1], v[2], a[0], a[1], a[2]]
}
