//! How an error in the aerodynamic specific force enters the state: the aerodynamic load at a
//! state and the map `G = ∂ẋ/∂δf` of a wind-frame specific-force error `δf` into the equations of
//! motion, for state-noise compensation (Tapley, Schutz & Born, *Statistical Orbit
//! Determination*, §4.9: an unmodelled acceleration as white noise mapped through `B = ∂ẋ/∂u`).
//!
//! The wind frame is [`wind_frame`]'s `[w_x, w_y, w_z]` (along the planet-relative velocity, to
//! its left, in the vertical plane), in which the specific force is `[−D, −L sinσ, L cosσ]`
//! (seed 003 eq. 3; seed 000 eq. 5). A density or C_D S/m error moves the whole vector with the
//! drag, an L/D error its lift part: both are errors of size ∝ |a_aero| in this frame.

use super::aero::{drag_lift, wind_frame};
use super::entry_model::EntryModel;
use super::kind::DynamicsKind;
use crate::atmosphere::Atmosphere;
use crate::math::{V3, cross, norm, sub};
use nalgebra::SMatrix;

/// The aerodynamic load at a state and how a specific-force error enters the state.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AeroNoiseMap<const N: usize> {
    /// Magnitude of the aerodynamic specific force |a_aero| = D·√(1 + (L/D)²) [m/s²].
    pub aero_accel_mps2: f64,
    /// Rate of change of the altitude ḣ \[m/s\].
    pub altitude_rate_mps: f64,
    /// `G = ∂ẋ/∂δf`: column `k` is the state derivative per m/s² of specific-force error along
    /// wind axis `k` (drag axis, side, lift plane).
    pub g: SMatrix<f64, N, 3>,
}

impl<A: Atmosphere> EntryModel<A> {
    /// The aerodynamic load and the specific-force error map at state `x` flying bank `bank`.
    ///
    /// Spherical states `[r, θ, λ, v, γ, ψ]` (seed 001 eq. 4–6): the specific force enters
    /// `v̇` as `f_x`, `γ̇` as `f_z / v` and `ψ̇` as `−f_y / (v cosγ)`; the position rows are zero.
    /// Cartesian states (seed 003 eq. 3): `v̇` gets `f_x w_x + f_y w_y + f_z w_z`. Augmented
    /// states are not driven.
    pub fn aero_noise_map<const N: usize>(
        &self,
        x: &nalgebra::SVector<f64, N>,
        bank: f64,
    ) -> AeroNoiseMap<N> {
        let p = self.aero_params(x, bank);
        let mut g = SMatrix::<f64, N, 3>::zeros();
        let (speed, altitude_rate) = match self.kind {
            DynamicsKind::Cartesian => {
                let r: V3<f64> = [x[0], x[1], x[2]];
                let v: V3<f64> = [x[3], x[4], x[5]];
                let v_rel = sub(&v, &cross(&[0.0, 0.0, self.omega()], &r));
                let rn = norm(&r);
                let axes = wind_frame(&r, &v_rel);
                for (k, w) in axes.iter().enumerate() {
                    for i in 0..3 {
                        g[(3 + i, k)] = w[i];
                    }
                }
                let radial = (r[0] * v[0] + r[1] * v[1] + r[2] * v[2]) / rn;
                (norm(&v_rel), radial)
            }
            _ => {
                let (v, fpa) = (x[3], x[4]);
                g[(3, 0)] = 1.0;
                g[(5, 1)] = -1.0 / (v * fpa.cos());
                g[(4, 2)] = 1.0 / v;
                (v, v * fpa.sin())
            }
        };
        let rho = self.atmosphere.density(self.altitude(x)) * p.density_scale;
        let (d, l) = drag_lift(rho, speed, &p);
        AeroNoiseMap {
            aero_accel_mps2: d.hypot(l),
            altitude_rate_mps: altitude_rate,
            g,
        }
    }
}

/// A spherical-or-Cartesian MSL-like model with L/D augmented, for the tests of the noise map
/// and of the process-noise models built on it.
#[cfg(test)]
pub(crate) fn test_model(kind: DynamicsKind) -> EntryModel<crate::atmosphere::AtmosphereModel> {
    use super::augmented_param::AugmentedParam;
    use super::entry_model::Vehicle;
    use crate::atmosphere::{AtmosphereModel, Exponential};
    use crate::planet::Planet;
    EntryModel {
        kind,
        planet: Planet::MARS,
        atmosphere: AtmosphereModel::Exponential(Exponential::mars_reference(Planet::MARS.radius)),
        vehicle: Vehicle {
            cd_s_over_m: 0.0146,
            lift_to_drag: 0.24,
        },
        augmented: vec![AugmentedParam::LiftToDrag],
        rho0_model: 1.0,
        density_factor: 1.0,
        bias_tau_s: None,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::atmosphere::AtmosphereModel;
    use nalgebra::{SVector, Vector3};

    /// ∂ẋ/∂s by central differences of the right-hand side for a parameter `s` set by `set`.
    fn fd(
        m: &EntryModel<AtmosphereModel>,
        x: &SVector<f64, 7>,
        bank: f64,
        set: impl Fn(&mut EntryModel<AtmosphereModel>, &mut SVector<f64, 7>, f64),
        s0: f64,
    ) -> SVector<f64, 7> {
        let e = 1e-6 * s0.abs().max(1e-3);
        let eval = |s: f64| {
            let (mut mm, mut xx) = (m.clone(), *x);
            set(&mut mm, &mut xx, s);
            mm.rhs(&xx, bank)
        };
        (eval(s0 + e) - eval(s0 - e)) / (2.0 * e)
    }

    /// A density error moves ẋ by G·f/ρ_scale and an L/D error by G·∂f/∂(L/D), with
    /// f = [−D, −L sinσ, L cosσ]: G checked against finite differences of the equations of
    /// motion in the drag and both lift directions (two bank angles), for both state kinds.
    #[test]
    fn the_map_matches_finite_differences_of_the_equations() {
        let cases = [
            (
                DynamicsKind::SphericalRotating,
                [3_440e3, 0.3, -0.4, 5_500.0, -0.2, 1.0],
            ),
            (
                DynamicsKind::Cartesian,
                [2_000e3, 2_500e3, -1_200e3, -3_000.0, 2_500.0, 2_800.0],
            ),
        ];
        for (kind, k) in cases {
            let m = super::test_model(kind);
            let mut x = SVector::<f64, 7>::zeros();
            x.fixed_rows_mut::<6>(0).copy_from_slice(&k);
            x[6] = 0.24;
            for bank in [0.5_f64, 2.0] {
                let map = m.aero_noise_map(&x, bank);
                let d = map.aero_accel_mps2 / (1.0 + 0.24_f64 * 0.24).sqrt();
                assert!(d > 1.0, "{kind:?}: drag {d} m/s² too small to test");
                let f = Vector3::new(-d, -0.24 * d * bank.sin(), 0.24 * d * bank.cos());
                let by_density = fd(&m, &x, bank, |mm, _, s| mm.density_factor = s, 1.0);
                let by_ld = fd(&m, &x, bank, |_, xx, s| xx[6] = s, 0.24);
                let df_ld = Vector3::new(0.0, -d * bank.sin(), d * bank.cos());
                for (want, got) in [(by_density, map.g * f), (by_ld, map.g * df_ld)] {
                    let err = (want - got).norm() / want.norm();
                    assert!(err < 1e-6, "{kind:?} σ={bank}: relative error {err:e}");
                }
            }
        }
    }
}
