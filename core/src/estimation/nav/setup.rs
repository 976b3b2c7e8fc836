//! Per-run filter start and truth expressed in the filter's coordinates.

use crate::dynamics::AugmentedParam;
use crate::frames::{inertial_to_spherical, spherical_to_inertial};
use crate::math::wrap_pi;
use crate::scenario::{Scenario, TruthDraw};
use crate::sim::TruthSample;
use nalgebra::{SMatrix, SVector};
use rand::Rng;
use rand_distr::{Distribution, StandardNormal};

/// Start of a filter for one run.
#[derive(Debug, Clone, PartialEq)]
pub struct FilterStart<const N: usize> {
    /// Initial estimate.
    pub x0: SVector<f64, N>,
    /// Initial covariance (diagonal `filter.p0_diag`).
    pub p0: SMatrix<f64, N, N>,
    /// Process noise per filter step (diagonal `filter.q_diag`).
    pub q: SMatrix<f64, N, N>,
}

/// The truth of `sample` in the filter model's coordinates (six kinematic states, then the
/// augmented states' true values). An augmented state with no truth counterpart (ρ0 when the truth
/// atmosphere is not exponential) is NaN and is reported as unavailable, not as an error.
pub fn truth_in_filter_coords<const N: usize>(
    scenario: &Scenario,
    draw: &TruthDraw,
    sample: &TruthSample,
) -> SVector<f64, N> {
    let fm = &scenario.filter_model;
    let tm = &draw.model;
    let kin: [f64; 6] = match (tm.kind.is_cartesian(), fm.kind.is_cartesian()) {
        (false, false) | (true, true) => sample.state,
        (true, false) => sample.spherical,
        (false, true) => {
            let (p, v) = spherical_to_inertial(&sample.state, sample.t, tm.omega());
            [p[0], p[1], p[2], v[0], v[1], v[2]]
        }
    };
    let mut x = SVector::<f64, N>::from_element(f64::NAN);
    for k in 0..6.min(N) {
        x[k] = kin[k];
    }
    let rho0_truth = scenario
        .config
        .truth
        .atmosphere
        .reference_density()
        .map(|r| r * tm.density_factor);
    for (k, a) in fm.augmented.iter().enumerate() {
        if 6 + k >= N {
            break;
        }
        x[6 + k] = match a {
            AugmentedParam::Rho0 => rho0_truth.unwrap_or(f64::NAN),
            AugmentedParam::LiftToDrag => tm.vehicle.lift_to_drag,
            AugmentedParam::CdSOverM => tm.vehicle.cd_s_over_m,
        };
    }
    x
}

/// Estimation error x̂ − x with angles (longitude, heading) wrapped to (−π, π] for spherical states.
pub fn estimation_error<const N: usize>(
    scenario: &Scenario,
    estimate: &SVector<f64, N>,
    truth: &SVector<f64, N>,
) -> SVector<f64, N> {
    let mut e = estimate - truth;
    if !scenario.filter_model.kind.is_cartesian() && N >= 6 {
        e[1] = wrap_pi(e[1]);
        e[5] = wrap_pi(e[5]);
    }
    e
}

/// The filter start of one run: `filter.initial` as a fixed start (seed 000 Table 1), or, with
/// `filter.sample_initial_from_p0`, the truth plus a draw from N(0, P0) (seed 001 §V.B) using `rng`.
pub fn filter_start<const N: usize>(
    scenario: &Scenario,
    draw: &TruthDraw,
    t0_sample: &TruthSample,
    rng: &mut impl Rng,
) -> FilterStart<N> {
    let f = &scenario.config.filter;
    let p0 = SMatrix::<f64, N, N>::from_diagonal(&SVector::from_fn(|i, _| {
        f.p0_diag.get(i).copied().unwrap_or(1.0)
    }));
    let q = SMatrix::<f64, N, N>::from_diagonal(&SVector::from_fn(|i, _| {
        f.q_diag.get(i).copied().unwrap_or(0.0)
    }));
    let nominal =
        SVector::<f64, N>::from_fn(|i, _| scenario.filter_initial.get(i).copied().unwrap_or(0.0));
    let x0 = if f.sample_initial_from_p0 {
        let truth = truth_in_filter_coords::<N>(scenario, draw, t0_sample);
        SVector::from_fn(|i, _| {
            let z: f64 = StandardNormal.sample(rng);
            let centre = if truth[i].is_finite() {
                truth[i]
            } else {
                nominal[i]
            };
            centre + p0[(i, i)].sqrt() * z
        })
    } else {
        nominal
    };
    FilterStart { x0, p0, q }
}

/// Convert a filter estimate to planet-relative spherical `[r, lon, lat, v, fpa, heading]` at `t`.
pub fn estimate_spherical<const N: usize>(
    scenario: &Scenario,
    x: &SVector<f64, N>,
    t: f64,
) -> [f64; 6] {
    let fm = &scenario.filter_model;
    if fm.kind.is_cartesian() {
        inertial_to_spherical(
            &[x[0], x[1], x[2]],
            &[x[3], x[4], x[5]],
            t,
            fm.planet.rotation_rate,
        )
    } else {
        [x[0], x[1], x[2], x[3], x[4], x[5]]
    }
}
