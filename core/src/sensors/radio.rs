//! Two-way radio measurements between the vehicle and a beacon.

use crate::math::{Real, V3, dot, lift3, norm, sub};

/// Two-way range R = ‖r − r_B‖ \[m\] (seed 000 eq. 6, seed 002 eq. 6, seed 003 eq. 9).
#[inline]
pub fn range<T: Real>(r: &V3<T>, beacon_r: &V3<f64>) -> T {
    norm(&sub(r, &lift3(beacon_r)))
}

/// Range-rate Ṙ = (r − r_B)·(v − v_B)/R [m/s] in the inertial frame (seed 002 eq. 7, seed 003 eq. 10).
#[inline]
pub fn range_rate<T: Real>(r: &V3<T>, v: &V3<T>, beacon_r: &V3<f64>, beacon_v: &V3<f64>) -> T {
    let dr = sub(r, &lift3(beacon_r));
    let dv = sub(v, &lift3(beacon_v));
    dot(&dr, &dv) / norm(&dr)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn range_rate_is_time_derivative_of_range() {
        let (r, v) = ([1.0e6, 2.0e6, 3.0e6], [100.0, -50.0, 20.0]);
        let (rb, vb) = ([4.0e6, 0.0, 1.0e6], [0.0, 30.0, -10.0]);
        let h = 1e-3;
        let at = |t: f64| {
            let rt = [r[0] + v[0] * t, r[1] + v[1] * t, r[2] + v[2] * t];
            let bt = [rb[0] + vb[0] * t, rb[1] + vb[1] * t, rb[2] + vb[2] * t];
            range(&rt, &bt)
        };
        let fd = (at(h) - at(-h)) / (2.0 * h);
        assert!((fd - range_rate(&r, &v, &rb, &vb)).abs() < 1e-6);
    }
}
