//! One exact fusion of the local filters' updates of the common prior ([`fusion_pass`]): the
//! locals that measured, their fused estimate and covariance, the weights and NIS.

use super::fusion_exact::fuse_exact;
use super::local_update::local_update;
use super::prior_information::PriorInformation;
use crate::estimation::error::EstimationError;
use crate::estimation::linearization::LinearizedMeasurement;
use crate::math::all_finite;
use nalgebra::SMatrix;
use nalgebra::SVector;

/// One fusion of the locals' updates of the common prior (`x`, `p`), linearised at `lin`.
pub(super) struct FusionPass<const N: usize> {
    pub(super) x: SVector<f64, N>,
    pub(super) p: SMatrix<f64, N, N>,
    pub(super) weights: Vec<f64>,
    pub(super) nis: f64,
    pub(super) n_meas: usize,
    pub(super) nis_terms: Vec<(usize, f64)>,
    /// Locals whose update failed numerically (dropped from the fusion).
    pub(super) failed: Vec<usize>,
}

#[allow(clippy::too_many_arguments)]
pub(super) fn fusion_pass<const N: usize>(
    x: &SVector<f64, N>,
    p: &SMatrix<f64, N, N>,
    info: Option<&PriorInformation<N>>,
    lin: &SVector<f64, N>,
    items: &[(usize, LinearizedMeasurement<N>)],
    masks: &[(usize, &[usize])],
    n_locals: usize,
    n_consider: usize,
) -> Result<FusionPass<N>, EstimationError> {
    let mut updates = Vec::new();
    let mut slots = Vec::new();
    let mut failed = Vec::new();
    for &(i, mask) in masks {
        match local_update(x, p, lin, items, mask, n_consider) {
            Ok(Some(u)) => {
                updates.push(u);
                slots.push(i);
            }
            Ok(None) => {}
            Err(_) => failed.push(i),
        }
    }
    let mut weights = vec![0.0; n_locals];
    let (mut nis, mut n_meas, mut nis_terms) = (0.0, 0, Vec::new());
    for u in &updates {
        nis += u.nis;
        n_meas += u.nis_terms.len();
        nis_terms.extend(u.nis_terms.iter().copied());
    }
    let (xf, pf) = match updates.len() {
        0 => (*x, *p),
        1 => {
            weights[slots[0]] = 1.0;
            let post = updates[0].posterior(p);
            if !all_finite(post.as_slice()) {
                return Err(EstimationError::NonFinite {
                    what: "a local filter's update".into(),
                });
            }
            (updates[0].x, post)
        }
        _ => {
            let (xf, pf, w) = fuse_exact(p, info, &updates)?;
            for (&i, wi) in slots.iter().zip(w) {
                weights[i] = wi;
            }
            (xf, pf)
        }
    };
    Ok(FusionPass {
        x: xf,
        p: pf,
        weights,
        nis,
        n_meas,
        nis_terms,
        failed,
    })
}
