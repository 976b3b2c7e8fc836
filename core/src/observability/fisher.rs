//! Fisher information of radio measurements (seed 002 §3.2 and §4): the 3×3 FIM of the vehicle
//! position from ranges (eq. 25, 29, 33, 36) and from range-rates (eq. 43–45), of its velocity from
//! range-rates (eq. 42), their determinant and trace bounds (eq. 27–28, 37–41, 46) and the geometry
//! index I (eq. 54).
//!
//! Direction convention: `n_i` is the unit vector from beacon i to the vehicle, `(r − r_Bi)/R_i`,
//! which is ∂R_i/∂r (eq. 29) and ∂Ṙ_i/∂v (eq. 42). All positions and velocities are inertial \[m\],
//! [m/s]; σ in the measurement's unit (m or m/s).

use super::error::ObservabilityError;
use crate::math::{V3, cross, dot, norm, scale, sub};
use nalgebra::{Matrix3, Vector3};

/// Unit vector from `from` to `to`; `None` when they coincide or are not finite.
pub fn unit_vector(from: &V3<f64>, to: &V3<f64>) -> Option<V3<f64>> {
    let d = sub(to, from);
    let r = norm(&d);
    (r > 0.0 && r.is_finite()).then(|| scale(1.0 / r, &d))
}

fn outer(a: &V3<f64>, w: f64) -> Matrix3<f64> {
    let v = Vector3::from(*a);
    v * v.transpose() * w
}

/// `Σ σ_i⁻² a_i a_iᵀ` for vectors `a_i` and 1σ `sigma_i` (the form of eq. 36, 42 and 45).
pub fn information(vectors: &[V3<f64>], sigma: &[f64]) -> Matrix3<f64> {
    vectors
        .iter()
        .zip(sigma)
        .fold(Matrix3::zeros(), |acc, (a, s)| acc + outer(a, s.powi(-2)))
}

/// Position FIM from ranges to beacons at `beacons` with 1σ `sigma` (eq. 36): `Σ σ⁻² n nᵀ`.
/// Also the velocity FIM from range-rates with range-rate σ (eq. 42). A beacon at the vehicle's
/// position contributes nothing.
pub fn range_fim(vehicle: &V3<f64>, beacons: &[V3<f64>], sigma: &[f64]) -> Matrix3<f64> {
    let (dirs, sig): (Vec<V3<f64>>, Vec<f64>) = beacons
        .iter()
        .zip(sigma)
        .filter_map(|(b, s)| unit_vector(b, vehicle).map(|n| (n, *s)))
        .unzip();
    information(&dirs, &sig)
}

/// `V_i = L_i (v − v_Bi)` with `L_i = (I − n_i n_iᵀ)/R_i` (eq. 44): the gradient of the range-rate
/// to beacon i with respect to the vehicle position (eq. 43). Seed 002 writes the vehicle velocity v
/// for a beacon at rest; we use the relative velocity, which is the exact gradient for a moving one.
pub fn range_rate_position_gradient(
    vehicle_pos: &V3<f64>,
    vehicle_vel: &V3<f64>,
    beacon_pos: &V3<f64>,
    beacon_vel: &V3<f64>,
) -> Option<V3<f64>> {
    let d = sub(vehicle_pos, beacon_pos);
    let r = norm(&d);
    let n = unit_vector(beacon_pos, vehicle_pos)?;
    let dv = sub(vehicle_vel, beacon_vel);
    let along = dot(&n, &dv);
    Some(scale(1.0 / r, &sub(&dv, &scale(along, &n))))
}

/// Position FIM from range-rates (eq. 43, 45): `Σ σ_V⁻² V_i V_iᵀ`. `beacons` are inertial
/// (position, velocity) pairs.
pub fn range_rate_position_fim(
    vehicle_pos: &V3<f64>,
    vehicle_vel: &V3<f64>,
    beacons: &[(V3<f64>, V3<f64>)],
    sigma: &[f64],
) -> Matrix3<f64> {
    let (vs, sig): (Vec<V3<f64>>, Vec<f64>) = beacons
        .iter()
        .zip(sigma)
        .filter_map(|((bp, bv), s)| {
            range_rate_position_gradient(vehicle_pos, vehicle_vel, bp, bv).map(|v| (v, *s))
        })
        .unzip();
    information(&vs, &sig)
}

/// `Σ_{i<j<k} σ_i⁻² σ_j⁻² σ_k⁻² [a_i·(a_j × a_k)]²` — det of `Σ σ⁻² a aᵀ` by the Cauchy–Binet
/// expansion of eq. 37 (range) and eq. 46 (range-rate, with a = V).
pub fn det_by_triples(vectors: &[V3<f64>], sigma: &[f64]) -> f64 {
    let n = vectors.len().min(sigma.len());
    let mut s = 0.0;
    for i in 0..n {
        for j in i + 1..n {
            let c = cross(&vectors[j], &vectors[i]);
            for k in j + 1..n {
                let w = (sigma[i] * sigma[j] * sigma[k]).powi(-2);
                s += w * dot(&vectors[k], &c).powi(2);
            }
        }
    }
    s
}

/// Geometry index `I = Σ_{i<j<k} [n_i·(n_j × n_k)]²` (eq. 54) of unit vectors `n`; at most
/// C(N, 3), and `I = det(N_3)` (eq. 62) for three beacons.
pub fn geometry_index(directions: &[V3<f64>]) -> f64 {
    det_by_triples(directions, &vec![1.0; directions.len()])
}

/// `(N/3)³`: the largest possible `det(Σ n nᵀ)` over N unit vectors (seed 002 eq. 40, Table 1).
/// The eigenvalues λ of `Σ n nᵀ` are ≥ 0 with Σλ = tr = N, so det = Πλ ≤ (N/3)³ by AM–GM, with
/// equality iff `Σ n nᵀ = (N/3)·I` (a tight frame, which exists for every N ≥ 3).
pub fn max_det_bound(n: usize) -> f64 {
    (n as f64 / 3.0).powi(3)
}

/// Determinant, trace and the bounds of seed 002 for one 3×3 FIM.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FimSummary {
    /// Number of measurements (beacons) in the FIM.
    pub count: usize,
    /// `det F` [σ-unit⁻⁶ · state-unit⁻⁶ …] (eq. 37).
    pub det: f64,
    /// `tr F` (eq. 28).
    pub trace: f64,
    /// Eigenvalues of F, ascending.
    pub eigenvalues: [f64; 3],
    /// Numerical rank of F (1 for one beacon, 2 for two, 3 for three non-coplanar ones).
    pub rank: usize,
    /// `tr F⁻¹ = Σ 1/λ` (eq. 27), the Cramér–Rao bound on `tr P`; `None` when F is singular.
    pub trace_inverse: Option<f64>,
    /// `3/tr F` (eq. 28, 32, 35): a lower bound on `tr F⁻¹` and so on `tr P`.
    pub trace_lower_bound: f64,
    /// Smallest 1σ among the measurements.
    pub sigma_min: f64,
    /// `σ_min⁻⁶ Σ [n_i·(n_j × n_k)]²` (eq. 38): an upper bound on det F.
    pub det_upper_bound: f64,
    /// `(N/3)³ σ_min⁻⁶` (eq. 40): the largest det any geometry of N such beacons can give.
    pub det_max: f64,
    /// `3 σ_min²/N` (eq. 41): the smallest `3/tr F` any N such beacons can give.
    pub trace_lower_bound_best: f64,
}

/// Summarise the FIM built from gradient vectors `a_i` (unit directions for ranges) and 1σ `sigma`.
///
/// The eq. 38/40/41 bounds assume unit vectors (range, or range-rate w.r.t. velocity); for the
/// range-rate position FIM they are still computed from the given vectors but are not the paper's
/// bounds.
pub fn summarize(vectors: &[V3<f64>], sigma: &[f64]) -> Result<FimSummary, ObservabilityError> {
    if vectors.len() != sigma.len() {
        return Err(ObservabilityError::InvalidInput(format!(
            "{} gradient vectors but {} sigmas",
            vectors.len(),
            sigma.len()
        )));
    }
    if sigma.iter().any(|s| !(s.is_finite() && *s > 0.0))
        || vectors.iter().flatten().any(|v| !v.is_finite())
    {
        return Err(ObservabilityError::InvalidInput(
            "FIM inputs must be finite with positive sigmas".into(),
        ));
    }
    let f = information(vectors, sigma);
    let mut ev = f.symmetric_eigenvalues();
    ev.as_mut_slice().sort_by(f64::total_cmp);
    let eigenvalues = [ev[0].max(0.0), ev[1].max(0.0), ev[2].max(0.0)];
    let trace = f.trace();
    let tol = 3.0 * f64::EPSILON * eigenvalues[2];
    let rank = eigenvalues.iter().filter(|&&l| l > tol).count();
    let count = vectors.len();
    let sigma_min = sigma.iter().copied().fold(f64::INFINITY, f64::min);
    let s6 = sigma_min.powi(-6);
    let tri = det_by_triples(vectors, &vec![1.0; count]);
    Ok(FimSummary {
        count,
        det: f.determinant().max(0.0),
        trace,
        eigenvalues,
        rank,
        trace_inverse: (rank == 3).then(|| eigenvalues.iter().map(|l| 1.0 / l).sum()),
        trace_lower_bound: if trace > 0.0 {
            3.0 / trace
        } else {
            f64::INFINITY
        },
        sigma_min: if count > 0 { sigma_min } else { 0.0 },
        det_upper_bound: if count > 0 { s6 * tri } else { 0.0 },
        det_max: if count > 0 {
            max_det_bound(count) * s6
        } else {
            0.0
        },
        trace_lower_bound_best: if count > 0 {
            3.0 * sigma_min * sigma_min / count as f64
        } else {
            f64::INFINITY
        },
    })
}
