//! N free unit vectors without visibility constraints: `max det(Σ n nᵀ)`, whose optimum is
//! `(N/3)³` (seed 002 eq. 40, Table 1). A check of the search machinery on a problem with a known
//! answer.
//!
//! Each vector is parametrised by its colatitude θ ∈ [0, π] and longitude φ ∈ [0, 2π]
//! (`n = (sin θ cos φ, sin θ sin φ, cos θ)`), which is unit-length for every real (θ, φ), so the
//! search needs no constraint. The cost is `−det(Σ n nᵀ)/(N/3)³`.

use crate::error::OptimizerError;
use crate::progress::Progress;
use crate::search::minimize;
use crate::search_options::{SearchOptions, SearchResult};
use nalgebra::{Matrix3, Vector3};
use std::f64::consts::{PI, TAU};

/// The best geometry found for N free unit vectors.
#[derive(Debug, Clone, PartialEq)]
pub struct FreeResult {
    /// Number of vectors N.
    pub count: usize,
    /// Best `det(Σ n nᵀ)` found.
    pub det: f64,
    /// `(N/3)³`.
    pub bound: f64,
    /// The unit vectors.
    pub directions: Vec<[f64; 3]>,
    /// Search statistics.
    pub search: SearchResult,
}

fn directions(x: &[f64]) -> Vec<[f64; 3]> {
    x.chunks_exact(2)
        .map(|c| {
            let (st, ct) = c[0].sin_cos();
            let (sp, cp) = c[1].sin_cos();
            [st * cp, st * sp, ct]
        })
        .collect()
}

/// `det(Σ n nᵀ)` of unit vectors `dirs`.
pub fn frame_det(dirs: &[[f64; 3]]) -> f64 {
    dirs.iter()
        .fold(Matrix3::zeros(), |acc, d| {
            let u = Vector3::from(*d);
            acc + u * u.transpose()
        })
        .determinant()
}

/// Maximise `det(Σ n nᵀ)` over `count` ≥ 3 unit vectors.
pub fn free_unit_vectors(
    count: usize,
    opts: &SearchOptions,
    progress: Progress<'_>,
) -> Result<FreeResult, OptimizerError> {
    if count < 3 {
        return Err(OptimizerError::Infeasible(format!(
            "{count} unit vector(s) span at most a plane: det(sum n n^T) = 0 for every geometry"
        )));
    }
    let bound = (count as f64 / 3.0).powi(3);
    let cost = |x: &[f64]| -frame_det(&directions(x)) / bound;
    let lower = vec![0.0; 2 * count];
    let upper: Vec<f64> = (0..count).flat_map(|_| [PI, TAU]).collect();
    let search = minimize(&cost, &lower, &upper, opts, progress)?;
    let dirs = directions(&search.x);
    Ok(FreeResult {
        count,
        det: frame_det(&dirs),
        bound,
        directions: dirs,
        search,
    })
}
