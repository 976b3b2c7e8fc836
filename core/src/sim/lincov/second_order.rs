//! The second-order mean drift of a filter's time update (`LinCovOptions::second_order_mean`).
//!
//! The first-order recursion ([`super`]) propagates the deviation of the filter's estimate from
//! the nominal, δx̂, through the Jacobian Φ of its own one-step map F at the nominal x̄. To second
//! order
//!
//! ```text
//! F(x̄ + δx̂) = F(x̄) + Φ δx̂ + ½ Σ_ab ∂²F/∂x_a∂x_b δx̂_a δx̂_b,
//! ```
//!
//! (the mean term of the truncated second-order filter, Gelb, *Applied Optimal Estimation*, 1974,
//! ch. 6), and the truth, flown by the same dynamics, has the same term in its own deviation
//! δx = Sθ.
//! The error's mean therefore gains, per step,
//!
//! ```text
//! b_j = ½ Σ_ab ∂²F_j/∂x_a∂x_b (E[δx̂ δx̂ᵀ] − E[δx δxᵀ])_ab,
//! ```
//!
//! which the first-order recursion drops. The measurement has the same term: the filter predicts
//! h(x̂), whose mean exceeds the truth's h(x) by c = ½ Σ_ab ∂²h/∂x_a∂x_b (E\[δx̂δx̂ᵀ\] −
//! E\[δxδxᵀ\])_ab, so each update's mean gains −K c. Both matter where a filter's error is large
//! where its models are curved: a CI local filter with one range keeps a km-sized altitude error
//! through the exponential density of its drag (docs/results.md, CI on orbiters-3), while a
//! dynamic-pressure measurement, as curved in the density as the drag, takes most of such a
//! drift back (msl-pressure). The second derivatives are central differences of the filter's own
//! Φ (RK4 sub-steps and all) and measurement Jacobians at x̄ ± h_a e_a, h_a a tenth of the largest
//! RMS deviation of state a. Only the mean is carried: the covariance's fourth-moment terms and
//! the truth model's difference from the filter's in the second derivatives are not.

use super::ekf_steps::time_update;
use super::error::EntryLinCovError;
use crate::beacons::BeaconState;
use crate::estimation::nav::EkfNav;
use crate::sensors::MeasurementEpoch;
use nalgebra::{DMatrix, SMatrix, SVector};

/// E\[δx̂δx̂ᵀ\] − E\[δxδxᵀ\] per filter, and the finite-difference step per state.
fn excess<const N: usize>(
    xbar: &SVector<f64, N>,
    second_moments: &[SMatrix<f64, N, N>],
    s: &DMatrix<f64>,
) -> (Vec<SMatrix<f64, N, N>>, SVector<f64, N>) {
    let sst = s * s.transpose();
    let truth = SMatrix::<f64, N, N>::from_fn(|r, c| sst[(r, c)]);
    let steps = SVector::<f64, N>::from_fn(|a, _| {
        let spread = second_moments
            .iter()
            .map(|m| m[(a, a)])
            .fold(0.0, f64::max)
            .sqrt();
        (0.1 * spread).max(1e-9 * (1.0 + xbar[a].abs()))
    });
    (second_moments.iter().map(|m| m - truth).collect(), steps)
}

/// c\[i\]\[j\] = ½ Σ_ab ∂²h_j/∂x_a∂x_b D_i,ab for every filter i and scalar measurement j of
/// `slots` at `epoch` (D_i from the prior's second moments and the truth's S at this epoch).
pub(super) fn measurement_bias<const N: usize>(
    nav: &EkfNav<N>,
    xbar: &SVector<f64, N>,
    (epoch, beacons, slots): (&MeasurementEpoch, &[BeaconState], &[usize]),
    second_moments: &[SMatrix<f64, N, N>],
    s: &DMatrix<f64>,
) -> Result<Vec<Vec<f64>>, EntryLinCovError> {
    let (d, steps) = excess(xbar, second_moments, s);
    let mut c = vec![vec![0.0; slots.len()]; d.len()];
    for a in 0..N {
        let rows = [1.0, -1.0].map(|sign| {
            let mut x = *xbar;
            x[a] += sign * steps[a];
            nav.items_at(&x, epoch, beacons, slots)
        });
        for (j, (plus, minus)) in rows[0].iter().zip(&rows[1]).enumerate() {
            // ∂²h/∂x_a∂x_· as a row.
            let dh = (plus.1 - minus.1) / (2.0 * steps[a]);
            for (ci, di) in c.iter_mut().zip(&d) {
                ci[j] += 0.5 * dh.dot(&di.row(a).transpose());
            }
        }
    }
    if c.iter().flatten().any(|v| !v.is_finite()) {
        return Err(EntryLinCovError::NonFinite {
            what: "the second-order measurement mean".into(),
            t: epoch.t,
        });
    }
    Ok(c)
}

/// b_i for every filter i whose estimate-deviation second moment E\[δx̂_i δx̂_iᵀ\] is
/// `second_moments[i]`, `nav` at the nominal `xbar` with covariance `p` before its time update
/// to `t`, and `s_prev` the truth's S at the previous epoch (E\[δx δxᵀ\] = S Sᵀ).
pub(super) fn mean_drift<const N: usize>(
    nav: &EkfNav<N>,
    xbar: &SVector<f64, N>,
    p: &SMatrix<f64, N, N>,
    t: f64,
    second_moments: &[SMatrix<f64, N, N>],
    s_prev: &DMatrix<f64>,
) -> Result<Vec<SVector<f64, N>>, EntryLinCovError> {
    let (d, steps) = excess(xbar, second_moments, s_prev);
    let mut b = vec![SVector::<f64, N>::zeros(); second_moments.len()];
    for a in 0..N {
        let h = steps[a];
        let mut phi = [SMatrix::<f64, N, N>::zeros(); 2];
        for (sign, out) in [1.0, -1.0].into_iter().zip(phi.iter_mut()) {
            let mut probe = nav.clone();
            let mut x = *xbar;
            x[a] += sign * h;
            probe.set_estimate(x, *p);
            *out = time_update(std::slice::from_mut(&mut probe), t).map_err(|e| {
                EntryLinCovError::SecondOrder {
                    t,
                    state: format!("#{a}"),
                    step: h,
                    reason: e.to_string(),
                }
            })?;
        }
        // Row j, column c of dΦ/dx_a is ∂²F_j/∂x_a∂x_c.
        let dphi = (phi[0] - phi[1]) / (2.0 * h);
        for (bi, di) in b.iter_mut().zip(&d) {
            *bi += 0.5 * dphi * di.row(a).transpose();
        }
    }
    if b.iter().any(|v| v.iter().any(|x| !x.is_finite())) {
        return Err(EntryLinCovError::NonFinite {
            what: "the second-order mean drift".into(),
            t,
        });
    }
    Ok(b)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::estimation::Onboard;
    use crate::estimation::nav::{FilterCore, FilterKind};
    use crate::scenario::{Scenario, ScenarioConfig};
    use crate::sim::lincov::ekf_steps::{fill, start};
    use crate::sim::lincov::truth::{NominalTruth, nominal_truth};
    use std::sync::Arc;

    /// orbiters-3's nominal truth and an EKF at its start, with P0.
    fn orbiters_3() -> (Arc<Onboard>, NominalTruth, EkfNav<6>, SMatrix<f64, 6, 6>) {
        let s = Scenario::build(
            ScenarioConfig::builtin("orbiters-3").unwrap(),
            &crate::files::no_files,
        )
        .unwrap();
        let onboard = s.onboard.for_filter(FilterKind::Ekf);
        let truth = nominal_truth(&s, 6).unwrap();
        let st = start::<6>(&s, &onboard, &truth);
        let nav = EkfNav::<6>::new(&onboard, &st.filter, None, 1.0).unwrap();
        (onboard, truth, nav, st.filter.p0)
    }

    /// A lower-triangular root L of the deviation's second moment L Lᵀ: 1 km and 0.5 m/s,
    /// correlated.
    fn deviation_root() -> SMatrix<f64, 6, 6> {
        SMatrix::from_fn(|r, c| match (r < 3, c < 3) {
            _ if r < c => 0.0,
            (true, true) => 1e3 * if r == c { 1.0 } else { 0.3 },
            (false, false) => 0.5 * if r == c { 1.0 } else { 0.2 },
            _ => 0.1,
        })
    }

    /// Against the mean of the filter's step over a Gaussian deviation by the unscented
    /// transform (2N points x̄ ± √N L_a, exact for a quadratic map), on orbiters-3 at t = 59 s
    /// where the drag is ≈ 30 m/s² and curved on a 7.5 km scale: with 1 km and 0.5 m/s the
    /// quartic terms the transform also picks up are ≈ (√6 km / 7.5 km)²/12 ≈ 1 % of the
    /// quadratic ones (measured: 0.7 % of the largest component; the drift is −0.32 m/s along
    /// the velocity, the extra deceleration of a density averaged over the altitude error).
    #[test]
    fn the_drift_is_the_mean_of_the_step_over_a_gaussian_deviation() {
        let (_, truth, mut nav, p) = orbiters_3();
        let k = 58;
        time_update(std::slice::from_mut(&mut nav), truth.epochs[k].t).unwrap();
        let xbar = fill(&truth.epochs[k].x, &SVector::<f64, 6>::zeros());
        let t = truth.epochs[k + 1].t;
        let l = deviation_root();
        let d = l * l.transpose();
        let b = mean_drift(&nav, &xbar, &p, t, &[d], &DMatrix::zeros(6, 0)).unwrap()[0];
        let step = |x: SVector<f64, 6>| {
            let mut n = nav.clone();
            n.set_estimate(x, p);
            time_update(std::slice::from_mut(&mut n), t).unwrap();
            n.state().0
        };
        let mut mean = SVector::<f64, 6>::zeros();
        for a in 0..6 {
            for sign in [1.0, -1.0] {
                mean += step(xbar + sign * 6f64.sqrt() * l.column(a)) / 12.0;
            }
        }
        let ut = mean - step(xbar);
        let scale = ut.amax();
        assert!(scale > 1e-2, "no curvature to test: {ut}");
        for j in 0..6 {
            assert!(
                (b[j] - ut[j]).abs() <= 0.02 * scale,
                "component {j}: drift {} vs unscented mean {} (of {ut})",
                b[j],
                ut[j]
            );
        }
        // Where the truth deviates as much as the estimate, the error gains no mean.
        let s_prev = DMatrix::from_fn(6, 6, |r, c| l[(r, c)]);
        let none = mean_drift(&nav, &xbar, &p, t, &[d], &s_prev).unwrap()[0];
        assert!(none.amax() < 1e-9 * scale.max(1.0), "{none}");
    }

    /// The measurement term against the unscented mean of the filter's three orbiter ranges over
    /// the same deviation at t = 60 s (≈ 1 m: (1 km)² over ≥ 600 km).
    #[test]
    fn the_measurement_bias_is_the_mean_of_the_predicted_ranges_over_a_gaussian_deviation() {
        let (onboard, truth, nav, _) = orbiters_3();
        let ep = &truth.epochs[59];
        let xbar = fill(&ep.x, &SVector::<f64, 6>::zeros());
        let beacons = onboard.beacon_states(ep.t);
        let slots: Vec<usize> = ep.meas.iter().map(|z| z.slot).collect();
        assert_eq!(slots.len(), 3);
        let l = deviation_root();
        let d = l * l.transpose();
        let at = (&ep.epoch, &beacons[..], &slots[..]);
        let c = measurement_bias(&nav, &xbar, at, &[d], &DMatrix::zeros(6, 0)).unwrap();
        let h = |x: SVector<f64, 6>| nav.values_at(&x, &ep.epoch, &beacons, &slots);
        let h0 = h(xbar);
        let mut mean = [0.0; 3];
        for a in 0..6 {
            for sign in [1.0, -1.0] {
                for (m, v) in mean
                    .iter_mut()
                    .zip(h(xbar + sign * 6f64.sqrt() * l.column(a)))
                {
                    *m += v / 12.0;
                }
            }
        }
        for j in 0..3 {
            let ut = mean[j] - h0[j];
            assert!(ut.abs() > 0.1, "range {j}: no curvature to test ({ut} m)");
            assert!(
                (c[0][j] - ut).abs() <= 0.01 * ut.abs(),
                "range {j}: {} m vs unscented {ut} m",
                c[0][j]
            );
        }
    }
}
