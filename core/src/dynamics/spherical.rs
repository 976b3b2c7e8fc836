//! Spherical 3-DOF point-mass entry dynamics over a spherical, possibly rotating planet.

use super::aero::{AeroParams, drag_lift};
use crate::atmosphere::Atmosphere;
use crate::math::Real;
use crate::planet::Planet;

/// Time derivative of the spherical state `[r, θ, λ, v, γ, ψ]` (north-clockwise heading, planet-
/// relative velocity), seed 001 eq. 1–6 with planet rotation ω, which reduce to seed 000 eq. 1 (and
/// seed 001 eq. 9–11) for ω = 0:
///
/// ```text
/// ṙ = v sinγ
/// θ̇ = v cosγ sinψ / (r cosλ)
/// λ̇ = v cosγ cosψ / r
/// v̇ = −D − g sinγ + ω² r cosλ (sinγ cosλ − cosγ sinλ cosψ)
/// γ̇ = [L cosσ − g cosγ + (v²/r) cosγ + 2ωv cosλ sinψ + ω² r cosλ (cosγ cosλ + sinγ sinλ cosψ)] / v
/// ψ̇ = [L sinσ / cosγ + (v²/r) cosγ sinψ tanλ − 2ωv (tanγ cosλ cosψ − sinλ)
///       + ω² r sinλ cosλ sinψ / cosγ] / v
/// ```
///
/// with g = μ/r², D and L from [`drag_lift`] and ρ = `density_scale`·ρ_model(r − R).
///
/// Seed 002 eq. 1 is the same model in the east-heading convention with the ω² terms dropped;
/// its printed Coriolis terms put the heading term on γ̇, which we read as a misprint and follow
/// seed 001 (validated against the Cartesian inertial model in the tests).
pub fn spherical_rhs<T: Real, A: Atmosphere>(
    x: &[T; 6],
    aero: &AeroParams<T>,
    atmosphere: &A,
    planet: &Planet,
    omega: f64,
) -> [T; 6] {
    let [r, _lon, lat, v, fpa, psi] = *x;
    let g = r.powi(2).recip() * planet.mu;
    let rho = atmosphere.density(r - planet.radius) * aero.density_scale;
    let (d, l) = drag_lift(rho, v, aero);
    let (sg, cg) = (fpa.sin(), fpa.cos());
    let (sl, cl) = (lat.sin(), lat.cos());
    let (sp, cp) = (psi.sin(), psi.cos());
    let (sb, cb) = (aero.bank.sin(), aero.bank.cos());
    let v_over_r = v / r;

    let r_dot = v * sg;
    let lon_dot = v * cg * sp / (r * cl);
    let lat_dot = v_over_r * cg * cp;
    let mut v_dot = -d - g * sg;
    let mut fpa_dot = (l * cb - g * cg) / v + v_over_r * cg;
    let mut psi_dot = l * sb / (v * cg) + v_over_r * cg * sp * sl / cl;
    if omega != 0.0 {
        let w = T::from(omega);
        let w2r = r * (omega * omega);
        v_dot += w2r * cl * (sg * cl - cg * sl * cp);
        fpa_dot += (w * v * cl * sp * 2.0 + w2r * cl * (cg * cl + sg * sl * cp)) / v;
        psi_dot += (-(w * v * (sg / cg * cl * cp - sl)) * 2.0 + w2r * sl * cl * sp / cg) / v;
    }
    [r_dot, lon_dot, lat_dot, v_dot, fpa_dot, psi_dot]
}
