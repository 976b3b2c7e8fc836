//! [`EntryModel`]: an entry vehicle ([`Vehicle`]) in an atmosphere over a planet, the right-hand
//! side of its equations of motion with augmented parameters, and its RK4 step with the
//! linearised state-transition matrix.

use super::aero::AeroParams;
use super::augmented_param::AugmentedParam;
use super::cartesian::cartesian_rhs;
use super::integrator::rk4_step;
use super::integrator::rk4_step_generic;
use super::kind::DynamicsKind;
use super::spherical::spherical_rhs;
use crate::atmosphere::Atmosphere;
use crate::math::Real;
use crate::math::ad_jacobian;
use crate::planet::Planet;
use nalgebra::SMatrix;
use nalgebra::SVector;
use serde::Deserialize;
use serde::Serialize;

/// The aerodynamic constants of a vehicle.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Vehicle {
    /// C_D·S/m [m²/kg]; the inverse of the ballistic coefficient m/(C_D S).
    pub cd_s_over_m: f64,
    /// Lift-to-drag ratio.
    pub lift_to_drag: f64,
}

/// An entry dynamics model: equations, planet, vehicle, atmosphere and augmented states.
#[derive(Debug, Clone, PartialEq)]
pub struct EntryModel<A> {
    /// Equations of motion.
    pub kind: DynamicsKind,
    /// Planet constants.
    pub planet: Planet,
    /// Density model.
    pub atmosphere: A,
    /// Vehicle constants (used where a quantity is not an augmented state).
    pub vehicle: Vehicle,
    /// Augmented constant states, in state order after the six kinematic states.
    pub augmented: Vec<AugmentedParam>,
    /// The atmosphere model's own reference density; an augmented ρ0 state scales the model
    /// density by ρ0/`rho0_model`.
    pub rho0_model: f64,
    /// Constant density factor 1 + Δ (seed 003 eq. 6: ρ = ρ_model·(1 + Δ)); 1 for the model itself.
    pub density_factor: f64,
    /// Time constant τ \[s\] of the accelerometer-bias states, first-order Gauss–Markov
    /// ḃ = −b/τ; `None`: random constants (ḃ = 0).
    pub bias_tau_s: Option<f64>,
}

impl<A: Atmosphere> EntryModel<A> {
    /// Planet rotation rate used by the equations (0 for [`DynamicsKind::Spherical`]).
    pub fn omega(&self) -> f64 {
        match self.kind {
            DynamicsKind::Spherical => 0.0,
            _ => self.planet.rotation_rate,
        }
    }

    /// State dimension: 6 plus the augmented states.
    pub fn state_dim(&self) -> usize {
        6 + self.augmented.len()
    }

    /// Aerodynamic parameters at state `x` (augmented states override the vehicle constants;
    /// augmented states beyond `N` are ignored and the vehicle constants used instead).
    pub fn aero_params<T: Real, const N: usize>(
        &self,
        x: &SVector<T, N>,
        bank: f64,
    ) -> AeroParams<T> {
        let mut p = AeroParams {
            cd_s_over_m: T::from(self.vehicle.cd_s_over_m),
            lift_to_drag: T::from(self.vehicle.lift_to_drag),
            bank: T::from(bank),
            density_scale: T::from(self.density_factor),
        };
        for (k, a) in self.augmented.iter().enumerate() {
            let Some(&val) = x.as_slice().get(6 + k) else {
                break;
            };
            match a {
                AugmentedParam::Rho0 => {
                    p.density_scale = val * (self.density_factor / self.rho0_model)
                }
                AugmentedParam::LiftToDrag => p.lift_to_drag = val,
                AugmentedParam::CdSOverM => p.cd_s_over_m = val,
                AugmentedParam::DensityBias => {
                    p.density_scale = (val + T::from(1.0)) * self.density_factor
                }
                AugmentedParam::AccelBiasX
                | AugmentedParam::AccelBiasY
                | AugmentedParam::AccelBiasZ => {}
            }
        }
        p
    }

    /// The C_D S/m the estimate `x` carries \[m²/kg\]: its augmented C_D S/m state when the model
    /// has one, `x` holds it and it is finite and positive, else the vehicle's constant. What the
    /// range trigger divides the sensed drag by to read the dynamic pressure onboard
    /// ([`crate::guidance::RangeTrigger::on_estimate`]).
    pub fn cd_s_over_m_of(&self, x: &[f64]) -> f64 {
        self.augmented
            .iter()
            .position(|a| *a == AugmentedParam::CdSOverM)
            .and_then(|k| x.get(6 + k).copied())
            .filter(|c| c.is_finite() && *c > 0.0)
            .unwrap_or(self.vehicle.cd_s_over_m)
    }

    /// The accelerometer bias the state `x` carries on IMU axis `axis`, if it has such a state.
    pub fn accel_bias<T: Real, const N: usize>(&self, x: &SVector<T, N>, axis: u8) -> Option<T> {
        self.augmented
            .iter()
            .position(|a| a.accel_axis() == Some(axis))
            .and_then(|k| x.as_slice().get(6 + k).copied())
    }

    /// `ẋ = f(x)` for the full (possibly augmented) state; augmented states have zero derivative,
    /// except accelerometer biases under a Gauss–Markov model (`bias_tau_s`): ḃ = −b/τ.
    pub fn rhs<T: Real, const N: usize>(&self, x: &SVector<T, N>, bank: f64) -> SVector<T, N> {
        let p = self.aero_params(x, bank);
        let k: [T; 6] = [x[0], x[1], x[2], x[3], x[4], x[5]];
        let d = match self.kind {
            DynamicsKind::Cartesian => {
                cartesian_rhs(&k, &p, &self.atmosphere, &self.planet, self.omega())
            }
            _ => spherical_rhs(&k, &p, &self.atmosphere, &self.planet, self.omega()),
        };
        let mut out = SVector::<T, N>::from_element(T::from(0.0));
        for i in 0..6 {
            out[i] = d[i];
        }
        if let Some(tau) = self.bias_tau_s {
            for (k, a) in self.augmented.iter().enumerate() {
                if a.accel_axis().is_some() && 6 + k < N {
                    out[6 + k] = -x[6 + k] / T::from(tau);
                }
            }
        }
        out
    }

    /// Exact Jacobian `∂f/∂x` by forward-mode AD, with `f(x)`.
    pub fn jacobian<const N: usize>(
        &self,
        x: &SVector<f64, N>,
        bank: f64,
    ) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
        ad_jacobian(|xd| self.rhs(&xd, bank), x)
    }

    /// One RK4 step of length `h` with constant bank angle.
    pub fn step<const N: usize>(&self, x: &SVector<f64, N>, bank: f64, h: f64) -> SVector<f64, N> {
        rk4_step(|y| self.rhs(y, bank), x, h)
    }

    /// One RK4 step with its exact state-transition matrix Φ = ∂x(t+h)/∂x(t) (AD through the step).
    pub fn step_with_stm<const N: usize>(
        &self,
        x: &SVector<f64, N>,
        bank: f64,
        h: f64,
    ) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
        ad_jacobian(|xd| rk4_step_generic(|y| self.rhs(y, bank), &xd, h), x)
    }

    /// One RK4 step with the *linearised* state-transition matrix
    /// Φ = I + hA + (hA)²/2! + (hA)³/3! + (hA)⁴/4! ≈ e^{hA}, with A = ∂f/∂x at the step's
    /// midpoint estimate x + (h/2)·k1 (forward-mode AD, one pass), as the EKF of seed 000 eq. 17
    /// linearises the dynamics.
    ///
    /// The mean is the same RK4 step as [`EntryModel::step`] (its second stage is the real part of
    /// the AD pass). Evaluating A at the midpoint makes Φ a second-order (midpoint/Magnus)
    /// approximation of the linearised flow; for linear dynamics it equals the exact Jacobian of
    /// the RK4 step ([`EntryModel::step_with_stm`]), for the entry dynamics the two differ by the
    /// change of A over one step (a test bounds the difference). It costs one AD pass instead of
    /// four, which is what keeps the EKF step within its budget.
    pub fn step_with_linear_stm<const N: usize>(
        &self,
        x: &SVector<f64, N>,
        bank: f64,
        h: f64,
    ) -> (SVector<f64, N>, SMatrix<f64, N, N>) {
        let k1 = self.rhs(x, bank);
        let (k2, a) = self.jacobian(&(x + k1 * (0.5 * h)), bank);
        let k3 = self.rhs(&(x + k2 * (0.5 * h)), bank);
        let k4 = self.rhs(&(x + k3 * h), bank);
        let x_next = x + (k1 + k2 * 2.0 + k3 * 2.0 + k4) * (h / 6.0);
        (x_next, taylor_stm(&a, h))
    }

    /// The transition matrix of [`EntryModel::step_with_linear_stm`] alone (bit for bit the
    /// same), without the RK4 stages it does not depend on: for a caller that takes the next
    /// state from elsewhere (the PCRLB, which has the recorded truth).
    pub fn linear_stm<const N: usize>(
        &self,
        x: &SVector<f64, N>,
        bank: f64,
        h: f64,
    ) -> SMatrix<f64, N, N> {
        let k1 = self.rhs(x, bank);
        let (_, a) = self.jacobian(&(x + k1 * (0.5 * h)), bank);
        taylor_stm(&a, h)
    }

    /// Altitude above the reference sphere of a state \[m\].
    pub fn altitude<const N: usize>(&self, x: &SVector<f64, N>) -> f64 {
        let r = if self.kind.is_cartesian() {
            (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt()
        } else {
            x[0]
        };
        r - self.planet.radius
    }

    /// Model density at a state [kg/m³], including an augmented ρ0 scale.
    pub fn density<const N: usize>(&self, x: &SVector<f64, N>) -> f64 {
        self.density_profile(x, self.altitude(x))
    }

    /// The model's density profile at `altitude_m` [kg/m³] with the density scale (augmented ρ0,
    /// bias factor) carried by the state `x` — the estimated profile of seed 001 eq. 70.
    pub fn density_profile<const N: usize>(&self, x: &SVector<f64, N>, altitude_m: f64) -> f64 {
        self.atmosphere.density(altitude_m) * self.aero_params(x, 0.0).density_scale
    }

    /// [`EntryModel::density_profile`] when the state estimates the density (an augmented ρ0),
    /// `None` otherwise: what a filter on this model reports as its density estimate.
    pub fn estimated_density_profile<const N: usize>(
        &self,
        x: &SVector<f64, N>,
        altitude_m: f64,
    ) -> Option<f64> {
        self.augmented
            .contains(&AugmentedParam::Rho0)
            .then(|| self.density_profile(x, altitude_m))
    }
}

/// Horner form of the degree-4 Taylor polynomial of exp(A h): I + M(I + M/2(I + M/3(I + M/4))).
///
/// The entry Jacobian is sparse (constant states have zero rows, longitude appears nowhere), so
/// each product M·Φ runs over M's non-zero entries only, row by row on a row-major Φ. Every
/// entry of a product is still summed in column order, as the dense product sums it, so the
/// result is the dense polynomial's bit for bit (skipped terms are exact zeros).
pub(super) fn taylor_stm<const N: usize>(a: &SMatrix<f64, N, N>, h: f64) -> SMatrix<f64, N, N> {
    let m = a * h;
    // Non-zero entries of M, row by row, in column order (at most N² of them).
    let mut entries: Vec<(usize, f64)> = Vec::with_capacity(N * N);
    let mut row_end = [0usize; N];
    for (i, end) in row_end.iter_mut().enumerate() {
        entries.extend((0..N).filter(|&k| m[(i, k)] != 0.0).map(|k| (k, m[(i, k)])));
        *end = entries.len();
    }
    let identity_row = |i: usize| std::array::from_fn::<f64, N, _>(|j| f64::from(u8::from(i == j)));
    // Φ ← I + c·(M·Φ), Φ row-major.
    let step = |phi: &[[f64; N]; N], c: f64| -> [[f64; N]; N] {
        let mut out = std::array::from_fn::<[f64; N], N, _>(identity_row);
        let mut start = 0;
        for (i, &end) in row_end.iter().enumerate() {
            let row = &entries[start..end];
            start = end;
            let Some((&(k0, m0), rest)) = row.split_first() else {
                continue;
            };
            let mut acc: [f64; N] = std::array::from_fn(|j| m0 * phi[k0][j]);
            for &(k, mk) in rest {
                for (x, p) in acc.iter_mut().zip(&phi[k]) {
                    *x += mk * p;
                }
            }
            for (o, x) in out[i].iter_mut().zip(&acc) {
                *o += x * c;
            }
        }
        out
    };
    // Ψ₄ = I + M/4, row-major.
    let mut phi: [[f64; N]; N] = std::array::from_fn(|i| {
        let mut r = identity_row(i);
        for (j, x) in r.iter_mut().enumerate() {
            *x += m[(i, j)] * 0.25;
        }
        r
    });
    phi = step(&phi, 1.0 / 3.0);
    phi = step(&phi, 0.5);
    phi = step(&phi, 1.0);
    SMatrix::from_fn(|i, j| phi[i][j])
}
