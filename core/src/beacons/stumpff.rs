//! [`stumpff`]: the Stumpff functions of the universal-variable formulation of two-body motion
//! ([`super::orbiter`]).

/// Stumpff functions `(C(z), S(z))` of the universal-variable formulation.
///
/// `C(z) = (1 − cos √z)/z`, `S(z) = (√z − sin √z)/√z³` for z > 0, their hyperbolic counterparts
/// for z < 0, and `C(0) = 1/2`, `S(0) = 1/6`. A power series is used for |z| < 1 and
/// `1 − cos x = 2 sin²(x/2)` elsewhere, so there is no cancellation near z = 0. Large negative z
/// overflows to +∞ (never NaN for finite z).
pub fn stumpff(z: f64) -> (f64, f64) {
    if z.abs() < 1.0 {
        // C = Σ (−z)^k/(2k+2)!, S = Σ (−z)^k/(2k+3)!; 12 terms reach below 1/25!.
        let (mut c, mut s) = (0.0, 0.0);
        let (mut tc, mut ts) = (0.5, 1.0 / 6.0);
        for k in 0..12 {
            c += tc;
            s += ts;
            let k = f64::from(k);
            tc *= -z / ((2.0 * k + 3.0) * (2.0 * k + 4.0));
            ts *= -z / ((2.0 * k + 4.0) * (2.0 * k + 5.0));
        }
        (c, s)
    } else if z > 0.0 {
        let x = z.sqrt();
        let h = (0.5 * x).sin();
        (2.0 * h * h / z, (x - x.sin()) / (z * x))
    } else {
        let x = (-z).sqrt();
        let h = (0.5 * x).sinh();
        (2.0 * h * h / -z, (x.sinh() - x) / (-z * x))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn stumpff_is_continuous_across_branches() {
        for &z in &[1.0 - 1e-12, -1.0 + 1e-12, 1.0 + 1e-12, -1.0 - 1e-12] {
            let (c, s) = stumpff(z);
            let (c1, s1) = stumpff(z.signum());
            assert!((c - c1).abs() < 1e-12 && (s - s1).abs() < 1e-12, "z={z}");
        }
        let (c, s) = stumpff(0.0);
        assert_eq!((c, s), (0.5, 1.0 / 6.0));
        // Series branch against the textbook formulas where those are still accurate.
        for &z in &[0.5f64, -0.5] {
            let (c, s) = stumpff(z);
            let x = z.abs().sqrt();
            let (c_ref, s_ref) = if z > 0.0 {
                ((1.0 - x.cos()) / z, (x - x.sin()) / x.powi(3))
            } else {
                ((x.cosh() - 1.0) / -z, (x.sinh() - x) / x.powi(3))
            };
            assert!(
                (c - c_ref).abs() < 1e-14 && (s - s_ref).abs() < 1e-14,
                "z={z}"
            );
        }
        let (c, s) = stumpff(-4.0e5);
        assert!(c.is_finite() && s.is_finite());
        // Beyond sinh's range the values overflow to +inf, never NaN.
        let (c, s) = stumpff(-1.0e7);
        assert!(c == f64::INFINITY && s == f64::INFINITY);
    }
}
