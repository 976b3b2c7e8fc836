//! Beacon geometry: the best possible directions for N range beacons (seed 002 eq. 39–40,
//! Table 1) and the range FIM and geometry index along a scenario's trajectory (Fig. 5–6).

use super::error::ObservabilityError;
use super::fisher::{FimSummary, geometry_index, summarize, unit_vector};
use super::system::AnalysisPoint;
use crate::math::{V3, dot, norm, scale};
use crate::scenario::Scenario;
use crate::sensors::Channel;
use crate::sensors::Noise;
use nalgebra::{Matrix3, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

/// The best `det(Σ n nᵀ)` found over N free unit vectors, and the directions.
#[derive(Debug, Clone, PartialEq)]
pub struct MaxDet {
    /// Largest determinant found (unit σ).
    pub det: f64,
    /// The N unit vectors achieving it.
    pub directions: Vec<V3<f64>>,
    /// Gradient-ascent iterations of the winning start.
    pub iterations: usize,
}

/// Maximise `det(Σ n_i n_iᵀ)` over N unit vectors (seed 002 eq. 39; the paper used a genetic
/// algorithm) by projected gradient ascent on `log det` from `starts` random starts drawn from
/// `seed`. The gradient of `log det F` with respect to `n_i` is `2 F⁻¹ n_i`; it is projected onto
/// the tangent plane of the unit sphere and each step is followed by renormalisation. N < 3 gives
/// det 0 (the FIM is singular for any geometry).
pub fn max_det_directions(n: usize, starts: usize, seed: u64) -> MaxDet {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut best = MaxDet {
        det: 0.0,
        directions: vec![[0.0, 0.0, 1.0]; n],
        iterations: 0,
    };
    if n < 3 {
        return best;
    }
    let step = n as f64 / 12.0;
    for _ in 0..starts.max(1) {
        let mut dirs: Vec<V3<f64>> = (0..n).map(|_| random_unit(&mut rng)).collect();
        let mut iterations = 0;
        for it in 0..20_000 {
            iterations = it + 1;
            let f = frame(&dirs);
            let Some(inv) = f.try_inverse() else { break };
            let mut moved = 0.0_f64;
            for d in dirs.iter_mut() {
                let g = inv * Vector3::from(*d) * 2.0;
                let g: V3<f64> = [g[0], g[1], g[2]];
                let radial = dot(&g, d);
                let tangent = [
                    g[0] - radial * d[0],
                    g[1] - radial * d[1],
                    g[2] - radial * d[2],
                ];
                moved = moved.max(norm(&tangent));
                let next = [
                    d[0] + step * tangent[0],
                    d[1] + step * tangent[1],
                    d[2] + step * tangent[2],
                ];
                *d = scale(1.0 / norm(&next), &next);
            }
            if moved < 1e-13 {
                break;
            }
        }
        let det = frame(&dirs).determinant();
        if det > best.det {
            best = MaxDet {
                det,
                directions: dirs,
                iterations,
            };
        }
    }
    best
}

fn frame(dirs: &[V3<f64>]) -> Matrix3<f64> {
    dirs.iter().fold(Matrix3::zeros(), |acc, d| {
        let v = Vector3::from(*d);
        acc + v * v.transpose()
    })
}

fn random_unit(rng: &mut ChaCha8Rng) -> V3<f64> {
    loop {
        let v: V3<f64> = [
            StandardNormal.sample(rng),
            StandardNormal.sample(rng),
            StandardNormal.sample(rng),
        ];
        let r = norm(&v);
        if r > 1e-6 {
            return scale(1.0 / r, &v);
        }
    }
}

/// The range FIM of the vehicle position at one analysis point.
#[derive(Debug, Clone, PartialEq)]
pub struct FimEpoch {
    /// Time \[s\].
    pub t: f64,
    /// Beacons (indices into the scenario's beacon list) whose ranges entered.
    pub beacons: Vec<usize>,
    /// det, trace and bounds (eq. 27–28, 37–41).
    pub summary: FimSummary,
    /// Geometry index I (eq. 54) of the beacon-to-vehicle unit vectors.
    pub geometry_index: f64,
}

/// Range FIM and geometry index at every analysis point, for the beacons with a range channel
/// (restricted to `subset` when given), skipping beacons unavailable at that point. Errors when the
/// scenario has no range channel in the selection.
pub fn range_fim_series(
    scenario: &Scenario,
    points: &[AnalysisPoint],
    subset: Option<&[usize]>,
) -> Result<Vec<FimEpoch>, ObservabilityError> {
    let ranged: Vec<(usize, f64)> = scenario
        .channels
        .iter()
        .filter_map(|c| match (c.channel, c.noise) {
            (Channel::Range(b), Noise::Absolute(s)) => Some((b, s)),
            _ => None,
        })
        .filter(|(b, _)| subset.is_none_or(|s| s.contains(b)))
        .collect();
    if ranged.is_empty() {
        return Err(ObservabilityError::NoBeacons {
            scenario: scenario.config.name.clone(),
            what: "range channels to analyse (the Fisher information needs range beacons)".into(),
        });
    }
    let mut out = Vec::with_capacity(points.len());
    for p in points {
        let mut beacons = Vec::new();
        let mut dirs = Vec::new();
        let mut sigma = Vec::new();
        for &(b, s) in &ranged {
            if !p.available.get(b).copied().unwrap_or(false) {
                continue;
            }
            let Some((bp, _)) = p.beacons.get(b) else {
                continue;
            };
            if let Some(n) = unit_vector(bp, &p.position) {
                beacons.push(b);
                dirs.push(n);
                sigma.push(s);
            }
        }
        let summary = summarize(&dirs, &sigma).map_err(|e| e.at(p.t))?;
        out.push(FimEpoch {
            t: p.t,
            beacons,
            summary,
            geometry_index: geometry_index(&dirs),
        });
    }
    Ok(out)
}
