//! Air-data measurements.

use crate::math::Real;

/// Dynamic pressure q = ½ρv² \[Pa\] (seed 001 eq. 14, seed 003 eq. 11).
#[inline]
pub fn dynamic_pressure<T: Real>(rho: T, v: T) -> T {
    rho * v * v * 0.5
}

/// Sutton–Graves stagnation-point convective heating rate Q̇ = k·sqrt(ρ/R_n)·v³ [W/m²]
/// (seed 001 eq. 15; k = 1.9027e-4 kg^½/m for Mars, R_n the nose radius \[m\]).
#[inline]
pub fn sutton_graves_heating<T: Real>(rho: T, v: T, k: f64, nose_radius: f64) -> T {
    (rho / nose_radius).sqrt() * v * v * v * k
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn heating_matches_hand_value() {
        // ρ = 1e-4, v = 5000, k = 1.9027e-4, Rn = 1.125  →  1.9027e-4·sqrt(8.888…e-5)·1.25e11
        let q = sutton_graves_heating(1e-4, 5000.0, 1.9027e-4, 1.125);
        let expect = 1.9027e-4 * (1e-4f64 / 1.125).sqrt() * 1.25e11;
        assert!((q - expect).abs() < 1e-9 * expect);
        assert_eq!(dynamic_pressure(2.0, 3.0), 9.0);
    }
}
