//! The EKF's steps along the nominal that both recursions take ([`super::recursion`] for one
//! filter, [`super::fusion`] for its local filters): the start of the moments, the time update
//! with the filter's own model, the scalar gain, and small helpers.

use super::error::EntryLinCovError;
use super::truth::NominalTruth;
use crate::estimation::EstimationError;
use crate::estimation::Onboard;
use crate::estimation::nav::{EkfNav, FilterStart};
use crate::scenario::Scenario;
use crate::sim::engine::judge::estimation_error;
use nalgebra::{DMatrix, SMatrix, SVector};

/// ∂R_f/∂z of the variance the filter assumes for channel `slot` at the measured value `z`
/// (zero for an absolute σ; 2f²z for σ = f|z|).
pub(super) fn noise_slope(onboard: &Onboard, slot: usize, z: f64) -> f64 {
    let Some(spec) = onboard.channels.get(slot) else {
        return 0.0;
    };
    let var = |v: f64| spec.noise.sigma(v).powi(2);
    let dz = 1e-6 * z.abs().max(1e-12);
    (var(z + dz) - var(z - dz)) / (2.0 * dz)
}

/// Column `j` of `s` as an N-vector.
pub(super) fn column<const N: usize>(s: &DMatrix<f64>, j: usize) -> SVector<f64, N> {
    SVector::from_fn(|i, _| s[(i, j)])
}

/// `x` with its non-finite entries (no truth counterpart) taken from `fallback`.
pub(super) fn fill<const N: usize>(x: &[f64], fallback: &SVector<f64, N>) -> SVector<f64, N> {
    SVector::from_fn(|i, _| if x[i].is_finite() { x[i] } else { fallback[i] })
}

/// Why the filter failed along the nominal.
pub(super) fn failed(e: EstimationError) -> EntryLinCovError {
    EntryLinCovError::Filter(e.to_string())
}

/// The start of the recursion: the nominal x̄_0, the filter's start and the moments of its
/// deviation δx̂_0 (the rows c_j = E\[θ_j δx̂_0\], C_ĥĥ and the mean).
pub(super) struct Start<const N: usize> {
    pub xbar: SVector<f64, N>,
    pub filter: FilterStart<N>,
    pub c: Vec<SVector<f64, N>>,
    pub chh: SMatrix<f64, N, N>,
    pub m: SVector<f64, N>,
}

/// x̂_0 drawn around the truth (δx̂_0 = S_0θ + P0^½w) or the fixed nominal start.
pub(super) fn start<const N: usize>(
    sc: &Scenario,
    onboard: &Onboard,
    truth: &NominalTruth,
) -> Start<N> {
    let nominal_start =
        SVector::<f64, N>::from_fn(|i, _| onboard.initial_estimate.get(i).copied().unwrap_or(0.0));
    let xbar = fill(&truth.x0, &nominal_start);
    let filter = FilterStart::<N>::with_estimate(onboard, xbar.as_slice());
    let p_count = truth.params.len();
    let (c, chh, m) = if sc.config.filter.sample_initial_from_p0 {
        let c: Vec<SVector<f64, N>> = (0..p_count).map(|j| column(&truth.s0, j)).collect();
        let chh = c.iter().fold(filter.p0, |acc, s| acc + s * s.transpose());
        (c, chh, SVector::<f64, N>::zeros())
    } else {
        let m0 = estimation_error(sc, &nominal_start, &xbar);
        (vec![SVector::zeros(); p_count], SMatrix::zeros(), m0)
    };
    Start {
        xbar,
        filter,
        c,
        chh,
        m,
    }
}

/// Time update of `navs` (all holding the same estimate, each its own P) to `t` with the
/// filter's own model: every sub-step's mean and Φ from the first, as the EKF and the fusion's
/// shared prediction compute them. Returns the transition Φ over the whole step.
pub(super) fn time_update<const N: usize>(
    navs: &mut [EkfNav<N>],
    t: f64,
) -> Result<SMatrix<f64, N, N>, EntryLinCovError> {
    let mut phi = SMatrix::<f64, N, N>::identity();
    let Some(first) = navs.first() else {
        return Ok(phi);
    };
    let (steps, h, q) = first.substeps_to(t).map_err(failed)?;
    for _ in 0..steps {
        let (x_next, f) = navs[0].substep(h);
        let q_k = navs[0].substep_noise(h, &f, &q);
        for nav in navs.iter_mut() {
            nav.apply_substep(x_next, &f, &q_k).map_err(failed)?;
        }
        phi = f * phi;
    }
    for nav in navs.iter_mut() {
        nav.finish_prediction(t);
    }
    Ok(phi)
}

/// The EKF's scalar gain K = P h/(hᵀP h + r_f) with the consider rows zero, and hᵀP h + r_f.
pub(super) fn scalar_gain<const N: usize>(
    p: &SMatrix<f64, N, N>,
    hrow: &SVector<f64, N>,
    r_f: f64,
    n_consider: usize,
    t: f64,
) -> Result<(SVector<f64, N>, f64), EntryLinCovError> {
    let ph = p * hrow;
    let s = hrow.dot(&ph) + r_f;
    if !(s.is_finite() && s > 0.0) {
        return Err(EntryLinCovError::NonFinite {
            what: "innovation variance".into(),
            t,
        });
    }
    let mut k = ph / s;
    for i in N.saturating_sub(n_consider)..N {
        k[i] = 0.0;
    }
    Ok((k, s))
}
