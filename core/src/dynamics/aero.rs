//! Aerodynamic accelerations and the wind (velocity) frame.

use crate::math::{Real, V3, cross, norm, scale};

/// Aerodynamic quantities that enter the equations of motion, possibly estimated (dual) values.
#[derive(Debug, Clone, Copy)]
pub struct AeroParams<T> {
    /// Inverse ballistic coefficient B = C_D·S/m [m²/kg] (seed 000 eq. 2; seed 001 state `B`).
    pub cd_s_over_m: T,
    /// Lift-to-drag ratio L/D (seed 000 eq. 2).
    pub lift_to_drag: T,
    /// Bank angle σ \[rad\] (an input; zero in every paper scenario).
    pub bank: T,
    /// Multiplier on the atmosphere model's density (1 for the model itself; an augmented ρ0 state
    /// enters as ρ0/ρ0,model, seed 000 eq. 3 and §2.3.1).
    pub density_scale: T,
}

/// Drag and lift accelerations `(D, L)` [m/s²] for density `rho` and airspeed `v`:
/// D = ½ρv²·C_D S/m, L = D·L/D (seed 000 eq. 2; seed 001 eq. 7–8; seed 003 eq. 4).
#[inline]
pub fn drag_lift<T: Real>(rho: T, v: T, p: &AeroParams<T>) -> (T, T) {
    let d = rho * v * v * p.cd_s_over_m * 0.5;
    (d, d * p.lift_to_drag)
}

/// Wind-frame unit vectors `[w_x, w_y, w_z]` for relative velocity `v_rel` at position `r`
/// (seed 003 eq. 1–2): w_x along v_rel, w_y = −(w_x × r)/‖w_x × r‖ (horizontal, to the left of
/// the velocity), w_z = w_x × w_y (in the vertical plane, upward for level flight).
///
/// With this frame a bank angle σ puts lift at `−L sinσ w_y + L cosσ w_z` (seed 003 eq. 3), and
/// the accelerometer's velocity-frame specific force is `[−D, −L sinσ, L cosσ]`, which is seed
/// 000 eq. 5; seed 001 eq. 13 writes `+L sinσ` for its own y-axis orientation (σ = 0 in every
/// paper scenario, where the two agree).
pub fn wind_frame<T: Real>(r: &V3<T>, v_rel: &V3<T>) -> [V3<T>; 3] {
    let wx = scale(norm(v_rel).recip(), v_rel);
    let c = cross(&wx, r);
    let wy = scale(-norm(&c).recip(), &c);
    let wz = cross(&wx, &wy);
    [wx, wy, wz]
}

/// Specific force (non-gravitational acceleration) in the wind frame: `[−D, −L sinσ, L cosσ]`.
#[inline]
pub fn specific_force_wind<T: Real>(d: T, l: T, bank: T) -> V3<T> {
    [-d, -(l * bank.sin()), l * bank.cos()]
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::math::dot;

    #[test]
    fn wind_frame_is_right_handed_and_lift_points_up() {
        // Level flight eastward at lon = lat = 0: position +x, east is +y.
        let r: [f64; 3] = [3.5e6, 0.0, 0.0];
        let v: [f64; 3] = [0.0, 5000.0, 0.0];
        let [wx, wy, wz] = wind_frame(&r, &v);
        assert!((dot(&wx, &wy)).abs() < 1e-15 && (dot(&wy, &wz)).abs() < 1e-15);
        assert!((cross(&wx, &wy)[2] - wz[2]).abs() < 1e-15);
        // Up is +x here; north is +z.
        assert!(
            (wz[0] - 1.0).abs() < 1e-15,
            "lift axis must be radial up: {wz:?}"
        );
        assert!(
            (wy[2] - 1.0).abs() < 1e-15,
            "w_y must point north (left of eastward flight)"
        );
    }
}
