//! Covariance intersection (seed 000 eq. 19–22): optimal weights against closed forms and
//! brute-force searches, consistency with a known cross-covariance, the fast ∞-norm rule,
//! scale invariance, badly scaled entry covariances, feedback and error handling.

use entrynav::estimation::EstimationError;
use entrynav::estimation::ci::{
    CiResult, CiWeighting, FEEDBACK_WEIGHT_FLOOR, ci_fuse, ci_weights, covariance_intersection,
    covariance_intersection_from, covariance_intersection_with_gains, feedback,
};
use nalgebra::{DMatrix, Matrix2, SMatrix, SVector, Vector2};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

const METHODS: [CiWeighting; 3] = [
    CiWeighting::OptimalTrace,
    CiWeighting::OptimalDet,
    CiWeighting::FastInfNorm,
];

fn randn<const R: usize, const C: usize>(rng: &mut ChaCha8Rng) -> SMatrix<f64, R, C> {
    SMatrix::from_fn(|_, _| StandardNormal.sample(rng))
}

fn random_spd<const N: usize>(rng: &mut ChaCha8Rng) -> SMatrix<f64, N, N> {
    let a: SMatrix<f64, N, N> = randn(rng);
    a * a.transpose() + SMatrix::identity() * 0.1
}

fn min_eig(m: DMatrix<f64>) -> f64 {
    let m = (&m + m.transpose()) * 0.5;
    m.symmetric_eigenvalues().min()
}

fn inv<const N: usize>(p: &SMatrix<f64, N, N>) -> SMatrix<f64, N, N> {
    p.cholesky().unwrap().inverse()
}

/// The objectives as the module documents them: det P_CI and Σ_k (P_CI)_kk / p̄_k.
fn objective<const N: usize>(ps: &[SMatrix<f64, N, N>], w: &[f64], trace: bool) -> f64 {
    let y: SMatrix<f64, N, N> = ps.iter().zip(w).map(|(p, wi)| inv(p) * *wi).sum();
    let pci = inv(&y);
    if trace {
        let pbar: SVector<f64, N> =
            ps.iter().map(|p| p.diagonal()).sum::<SVector<f64, N>>() / ps.len() as f64;
        pci.diagonal().component_div(&pbar).sum()
    } else {
        pci.cholesky()
            .unwrap()
            .l()
            .diagonal()
            .map(|v| v * v)
            .product()
    }
}

/// Brute-force 1-D minimiser over ω ∈ [0, 1]: a 2 001-point grid, then golden section in the
/// bracketing cell.
fn brute_force_two<const N: usize>(ps: &[SMatrix<f64, N, N>; 2], trace: bool) -> f64 {
    let f = |w: f64| objective(ps, &[w, 1.0 - w], trace);
    let vals: Vec<f64> = (0..=2_000).map(|k| f(k as f64 * 5e-4)).collect();
    let k = (0..vals.len())
        .min_by(|&a, &b| vals[a].total_cmp(&vals[b]))
        .unwrap();
    let (mut lo, mut hi) = ((k as f64 - 1.0) * 5e-4, (k as f64 + 1.0) * 5e-4);
    (lo, hi) = (lo.max(0.0), hi.min(1.0));
    let r = (5f64.sqrt() - 1.0) / 2.0;
    for _ in 0..80 {
        let (a, b) = (hi - r * (hi - lo), lo + r * (hi - lo));
        if f(a) < f(b) { hi = b } else { lo = a }
    }
    0.5 * (lo + hi)
}

#[test]
fn single_and_identical_estimates() {
    let y = Matrix2::new(2.0, 0.5, 0.5, 1.0);
    for m in METHODS {
        assert_eq!(ci_weights(&[y], m).unwrap(), vec![1.0]);
        let w = ci_weights(&[y, y, y], m).unwrap();
        assert!(
            w.iter().all(|v| (v - 1.0 / 3.0).abs() < 1e-12),
            "{m:?}: {w:?}"
        );
        let r = covariance_intersection(&[(Vector2::new(1.0, 2.0), inv(&y))], m).unwrap();
        assert_eq!(r.weights, vec![1.0]);
        assert!(
            (r.p - inv(&y)).abs().max() < 1e-14
                && (r.x - Vector2::new(1.0, 2.0)).abs().max() < 1e-14
        );
    }
}

#[test]
fn scalar_case_picks_the_more_informative_estimate() {
    // 1-D: P_CI = 1/(ω/p1 + (1−ω)/p2) is monotone in ω, so both optima put all weight on p1 < p2.
    let est = [
        (SVector::<f64, 1>::new(1.0), SMatrix::<f64, 1, 1>::new(2.0)),
        (SVector::<f64, 1>::new(4.0), SMatrix::<f64, 1, 1>::new(5.0)),
    ];
    for m in [CiWeighting::OptimalTrace, CiWeighting::OptimalDet] {
        let r = covariance_intersection(&est, m).unwrap();
        assert!(
            (r.weights[0] - 1.0).abs() < 1e-12 && r.weights[1].abs() < 1e-12,
            "{m:?}: {:?}",
            r.weights
        );
        assert!((r.x[0] - 1.0).abs() < 1e-12 && (r.p[(0, 0)] - 2.0).abs() < 1e-12);
    }
    // eq. 21 by hand: Y = 0.5 + 0.2 = 0.7, ω1 = (0.7 − 0.2 + 0.5)/(2·0.7 + (0.5 − 0.2) + (0.2 − 0.5)).
    let r = covariance_intersection(&est, CiWeighting::FastInfNorm).unwrap();
    assert!((r.weights[0] - 1.0 / 1.4).abs() < 1e-14 && (r.weights[1] - 0.4 / 1.4).abs() < 1e-14);
    let y = 0.5 * r.weights[0] + 0.2 * r.weights[1];
    assert!((r.p[(0, 0)] - 1.0 / y).abs() < 1e-12);
    assert!((r.x[0] - (0.5 * r.weights[0] * 1.0 + 0.2 * r.weights[1] * 4.0) / y).abs() < 1e-12);
}

#[test]
fn two_estimates_2d_match_closed_form_and_brute_force() {
    let mut rng = ChaCha8Rng::seed_from_u64(11);
    let mut interior = 0;
    for case in 0..40 {
        let ps: [Matrix2<f64>; 2] = [random_spd(&mut rng), random_spd(&mut rng)];
        let (y1, y2) = (inv(&ps[0]), inv(&ps[1]));
        // det(Y2 + ω B), B = Y1 − Y2, is the quadratic det Y2 + ω tr(adj(Y2) B) + ω² det B.
        let b = y1 - y2;
        let adj = Matrix2::new(y2[(1, 1)], -y2[(0, 1)], -y2[(1, 0)], y2[(0, 0)]);
        let (c1, c2) = ((adj * b).trace(), b.determinant());
        let fd = |w: f64| -(y2.determinant() + w * c1 + w * w * c2);
        let mut best = if fd(0.0) < fd(1.0) { 0.0 } else { 1.0 };
        if c2 < 0.0 {
            let v = -c1 / (2.0 * c2);
            if (0.0..=1.0).contains(&v) && fd(v) < fd(best) {
                best = v;
                interior += 1;
            }
        }
        let wd = ci_weights(&[y1, y2], CiWeighting::OptimalDet).unwrap();
        assert!(
            (wd[0] - best).abs() < 1e-9,
            "case {case}: det {wd:?} vs closed form {best}"
        );
        assert!(
            (wd[0] - brute_force_two(&ps, false)).abs() < 1e-6,
            "case {case}: det brute force"
        );
        let wt = ci_weights(&[y1, y2], CiWeighting::OptimalTrace).unwrap();
        let bt = brute_force_two(&ps, true);
        assert!(
            (wt[0] - bt).abs() < 1e-6,
            "case {case}: trace {wt:?} vs brute force {bt}"
        );
        for w in [&wd, &wt] {
            assert!(
                w.iter().all(|v| (0.0..=1.0).contains(v))
                    && (w.iter().sum::<f64>() - 1.0).abs() < 1e-14
            );
        }
    }
    assert!(
        interior > 5,
        "too few interior optima exercised: {interior}"
    );
}

#[test]
fn optimal_weights_beat_a_simplex_grid_for_four_estimates() {
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    for _ in 0..10 {
        let ps: Vec<SMatrix<f64, 3, 3>> = (0..4).map(|_| random_spd(&mut rng)).collect();
        let infos: Vec<_> = ps.iter().map(inv).collect();
        for (m, trace) in [
            (CiWeighting::OptimalTrace, true),
            (CiWeighting::OptimalDet, false),
        ] {
            let w = ci_weights(&infos, m).unwrap();
            let fopt = objective(&ps, &w, trace);
            let k = 16;
            for a in 0..=k {
                for b in 0..=k - a {
                    for c in 0..=k - a - b {
                        let g = [a, b, c, k - a - b - c].map(|v| v as f64 / k as f64);
                        assert!(
                            fopt <= objective(&ps, &g, trace) * (1.0 + 1e-12),
                            "{m:?} {w:?} vs {g:?}"
                        );
                    }
                }
            }
        }
    }
}

/// The filters start each epoch's optimal-weight search from the last epoch's weights: from any
/// admissible start — a vertex (three weights starting inactive), the optimum itself, a nearby
/// point, or an unusable start (ignored) — the search reaches the cold start's optimum.
#[test]
fn warm_started_weights_reach_the_cold_optimum() {
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    let mut vertex_moved = 0;
    for _ in 0..20 {
        let est: Vec<(SVector<f64, 3>, SMatrix<f64, 3, 3>)> = (0..4)
            .map(|_| (randn(&mut rng), random_spd(&mut rng)))
            .collect();
        for (m, trace) in [
            (CiWeighting::OptimalTrace, true),
            (CiWeighting::OptimalDet, false),
        ] {
            let cold = covariance_intersection(&est, m).unwrap();
            let ps: Vec<_> = est.iter().map(|e| e.1).collect();
            let fcold = objective(&ps, &cold.weights, trace);
            let near: Vec<f64> = cold.weights.iter().map(|w| w + 0.05).collect();
            let starts: [&[f64]; 5] = [
                &[1.0, 0.0, 0.0, 0.0],
                &cold.weights,
                &near,
                &[0.0, 0.0, 0.0, 0.0],
                &[f64::NAN, 1.0, 0.0, 0.0],
            ];
            for start in starts {
                let warm = covariance_intersection_from(&est, m, start).unwrap();
                let fwarm = objective(&ps, &warm.weights, trace);
                assert!(
                    fwarm <= fcold * (1.0 + 1e-12),
                    "{m:?} from {start:?}: {:?} ({fwarm}) vs cold {:?} ({fcold})",
                    warm.weights,
                    cold.weights
                );
                // To the search's tolerance: its chord steps leave the weights within ~1e-7 of
                // the optimum (measured here: P within 2e-8, mostly 1e-10).
                assert!((warm.p - cold.p).abs().max() <= 1e-7 * cold.p.abs().max());
            }
            let from_vertex = covariance_intersection_from(&est, m, starts[0]).unwrap();
            vertex_moved += usize::from(from_vertex.weights[1..].iter().any(|w| *w > 1e-6));
        }
    }
    // The vertex start must have re-admitted weights that started at zero.
    assert!(vertex_moved > 5, "only {vertex_moved} vertex starts moved");
}

/// The fusion gains W_i = ω_i P_CI P_i⁻¹ reproduce the fused estimate (x̂_CI = Σ W_i x̂_i) and sum
/// to the identity, on badly scaled entry covariances.
#[test]
fn fusion_gains_reproduce_the_fused_estimate() {
    let mut rng = ChaCha8Rng::seed_from_u64(4);
    for _ in 0..10 {
        let est = entry_estimates(&mut rng);
        for m in METHODS {
            let (fused, gains) = covariance_intersection_with_gains(&est, m).unwrap();
            assert_eq!(fused, covariance_intersection(&est, m).unwrap());
            let x: SVector<f64, 8> = gains.iter().zip(&est).map(|(w, (xi, _))| w * xi).sum();
            let sum: SMatrix<f64, 8, 8> = gains.iter().sum();
            let scale = fused.p.diagonal().map(f64::sqrt);
            let dx = (x - fused.x).component_div(&scale).abs().max();
            assert!(dx < 1e-7, "{m:?}: Σ W_i x̂_i − x̂_CI = {dx:e} σ");
            let d = SMatrix::<f64, 8, 8>::from_fn(|r, c| {
                (sum[(r, c)] - if r == c { 1.0 } else { 0.0 }) * scale[c] / scale[r]
            });
            assert!(d.abs().max() < 1e-8, "{m:?}: Σ W_i − I = {}", d.abs().max());
            // Each gain is ω_i P_CI P_i⁻¹ (formed directly here, in the same scaled metric).
            for ((w, (_, p)), wi) in gains.iter().zip(&est).zip(&fused.weights) {
                let direct = fused.p * inv(p) * *wi;
                let d = SMatrix::<f64, 8, 8>::from_fn(|r, c| {
                    (w[(r, c)] - direct[(r, c)]) * scale[c] / scale[r]
                });
                assert!(d.abs().max() < 1e-6, "{m:?}: W_i off by {}", d.abs().max());
            }
        }
    }
}

#[test]
fn ci_is_consistent_for_every_weight_with_a_known_cross_covariance() {
    // e_i = A_i c + B_i v_i with a common c ~ N(0, I₄) and independent v_i: the true joint error
    // covariance is C_ij = A_i A_jᵀ + δ_ij B_i B_iᵀ, and each local P_i = C_ii is consistent.
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    for _ in 0..20 {
        let a: Vec<SMatrix<f64, 3, 4>> = (0..3).map(|_| randn(&mut rng)).collect();
        let b: Vec<SMatrix<f64, 3, 3>> = (0..3).map(|_| randn::<3, 3>(&mut rng) * 0.3).collect();
        let c = |i: usize, j: usize| {
            a[i] * a[j].transpose()
                + if i == j {
                    b[i] * b[i].transpose()
                } else {
                    SMatrix::zeros()
                }
        };
        let est: Vec<_> = (0..3)
            .map(|i| (SVector::<f64, 3>::zeros(), c(i, i)))
            .collect();
        let mut grid: Vec<[f64; 3]> = Vec::new();
        for p in 0..=10 {
            for q in 0..=10 - p {
                grid.push([p as f64 / 10.0, q as f64 / 10.0, (10 - p - q) as f64 / 10.0]);
            }
        }
        for m in METHODS {
            grid.push(
                covariance_intersection(&est, m)
                    .unwrap()
                    .weights
                    .try_into()
                    .unwrap(),
            );
        }
        for w in grid {
            let r = ci_fuse(&est, &w).unwrap();
            // x̂_CI − x = Σ K_i e_i with K_i = ω_i P_CI P_i⁻¹.
            let k: Vec<_> = (0..3).map(|i| r.p * inv(&est[i].1) * w[i]).collect();
            let mut mse = SMatrix::<f64, 3, 3>::zeros();
            for i in 0..3 {
                for j in 0..3 {
                    mse += k[i] * c(i, j) * k[j].transpose();
                }
            }
            let gap = min_eig(DMatrix::from_iterator(3, 3, (r.p - mse).iter().copied()));
            assert!(
                gap >= -1e-10 * r.p.norm(),
                "ω = {w:?}: P_CI − MSE has eigenvalue {gap}"
            );
        }
    }
}

#[test]
fn fast_weights_follow_eq_21() {
    // Hand-computed (‖·‖∞ = max absolute row sum):
    // Y1 = [[2,1],[1,3]] (4), Y2 = [[1,−½],[−½,1]] (1.5), Y = [[3,½],[½,4]] (4.5):
    // ω1 = (4.5 − 1.5 + 4)/(2·4.5 + (4 − 1.5) + (1.5 − 4)) = 7/9, ω2 = 2/9.
    let y1 = Matrix2::new(2.0, 1.0, 1.0, 3.0);
    let y2 = Matrix2::new(1.0, -0.5, -0.5, 1.0);
    let w = ci_weights(&[y1, y2], CiWeighting::FastInfNorm).unwrap();
    assert!(
        (w[0] - 7.0 / 9.0).abs() < 1e-15 && (w[1] - 2.0 / 9.0).abs() < 1e-15,
        "{w:?}"
    );
    // n = 3: Y = diag(4, 5) (5); ‖Y − Y_i‖ = 4, 4, 3; numerators 2, 3, 5; denominator 15 − 5.
    let ys = [
        Matrix2::identity(),
        Matrix2::new(2.0, 0.0, 0.0, 1.0),
        Matrix2::new(1.0, 0.0, 0.0, 3.0),
    ];
    let w = ci_weights(&ys, CiWeighting::FastInfNorm).unwrap();
    assert!(
        [0.2, 0.3, 0.5]
            .iter()
            .zip(&w)
            .all(|(e, v)| (e - v).abs() < 1e-15),
        "{w:?}"
    );
    // Identical estimates: equal weights; random ones: a valid simplex point.
    let w = ci_weights(&[y1; 4], CiWeighting::FastInfNorm).unwrap();
    assert!(w.iter().all(|v| (v - 0.25).abs() < 1e-15));
    let mut rng = ChaCha8Rng::seed_from_u64(9);
    for n in 1..6 {
        let ys: Vec<SMatrix<f64, 4, 4>> = (0..n).map(|_| random_spd(&mut rng)).collect();
        let w = ci_weights(&ys, CiWeighting::FastInfNorm).unwrap();
        assert!(
            w.iter().all(|v| *v >= 0.0) && (w.iter().sum::<f64>() - 1.0).abs() < 1e-14,
            "{w:?}"
        );
    }
}

#[test]
fn optimal_weights_are_invariant_to_state_rescaling() {
    let mut rng = ChaCha8Rng::seed_from_u64(77);
    let d = SMatrix::<f64, 4, 4>::from_diagonal(&SVector::from([1e3, 1e-6, 1.0, 1e5]));
    let t: SMatrix<f64, 4, 4> = randn::<4, 4>(&mut rng) + SMatrix::identity() * 3.0;
    for _ in 0..10 {
        let ps: Vec<SMatrix<f64, 4, 4>> = (0..4).map(|_| random_spd(&mut rng)).collect();
        let est = |m: &SMatrix<f64, 4, 4>| -> Vec<_> {
            ps.iter()
                .map(|p| (SVector::zeros(), m * p * m.transpose()))
                .collect()
        };
        let base = est(&SMatrix::identity());
        for m in [CiWeighting::OptimalDet, CiWeighting::OptimalTrace] {
            let w0 = covariance_intersection(&base, m).unwrap().weights;
            // Diagonal unit changes: both the determinant and the normalised trace are invariant.
            let w1 = covariance_intersection(&est(&d), m).unwrap().weights;
            assert!(
                w0.iter().zip(&w1).all(|(a, b)| (a - b).abs() < 1e-7),
                "{m:?}: {w0:?} vs {w1:?}"
            );
            // A general invertible change of coordinates: only the determinant is invariant.
            if m == CiWeighting::OptimalDet {
                let w2 = covariance_intersection(&est(&(d * t)), m).unwrap().weights;
                assert!(
                    w0.iter().zip(&w2).all(|(a, b)| (a - b).abs() < 1e-7),
                    "{w0:?} vs {w2:?}"
                );
            }
        }
    }
}

/// Four 8-state entry-filter-like covariances: variances 1e6 m² … 1e-12 rad², correlations
/// up to ~0.95.
fn entry_estimates(rng: &mut ChaCha8Rng) -> Vec<(SVector<f64, 8>, SMatrix<f64, 8, 8>)> {
    let sig = SVector::<f64, 8>::from([1e3, 1e-6, 1e-6, 1e1, 1e-2, 1e-2, 1e-1, 1e-1]);
    (0..4)
        .map(|i| {
            let a: SMatrix<f64, 8, 8> = randn(rng);
            let corr = a * a.transpose() + SMatrix::identity() * 0.05 * (i + 1) as f64;
            let dn = corr.diagonal().map(|v| 1.0 / v.sqrt());
            let s = sig * 10f64.powf(i as f64 * 0.3 - 0.5);
            let p =
                SMatrix::<f64, 8, 8>::from_fn(|r, c| corr[(r, c)] * dn[r] * dn[c] * s[r] * s[c]);
            let x = SVector::<f64, 8>::from_fn(|k, _| {
                s[k] * Distribution::<f64>::sample(&StandardNormal, rng)
            });
            (x, p)
        })
        .collect()
}

#[test]
fn badly_scaled_entry_covariances_give_finite_pd_results() {
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    for _ in 0..20 {
        let est = entry_estimates(&mut rng);
        let sig = est[0].1.diagonal().map(f64::sqrt);
        let scaled = |m: &SMatrix<f64, 8, 8>| {
            SMatrix::<f64, 8, 8>::from_fn(|r, c| m[(r, c)] / (sig[r] * sig[c]))
        };
        for m in METHODS {
            let r = covariance_intersection(&est, m).unwrap();
            assert!(r.x.iter().chain(r.p.iter()).all(|v| v.is_finite()));
            assert!(r.p.cholesky().is_some(), "{m:?}: P_CI not PD");
            assert!(r.weights.iter().all(|v| (0.0..=1.0).contains(v)));
            // CI bound P_CI ⪯ P_i / ω_i (since P_CI⁻¹ ⪰ ω_i P_i⁻¹), checked in scaled units.
            for ((_, p), w) in est.iter().zip(&r.weights) {
                if *w > 1e-3 {
                    let gap = scaled(&(p / *w - r.p));
                    assert!(
                        min_eig(DMatrix::from_iterator(8, 8, gap.iter().copied())) > -1e-8,
                        "{m:?}"
                    );
                }
            }
            // Weights from the information matrices directly agree with the fused ones.
            let infos: Vec<_> = est.iter().map(|(_, p)| inv(p)).collect();
            let w = ci_weights(&infos, m).unwrap();
            assert!(
                w.iter().zip(&r.weights).all(|(a, b)| (a - b).abs() < 1e-6),
                "{m:?}: {w:?} vs {:?}",
                r.weights
            );
        }
    }
}

/// max_ij |a − b|_ij / √(b_ii b_jj): an error measure that is fair to badly scaled matrices.
fn scaled_err<const N: usize>(a: &SMatrix<f64, N, N>, b: &SMatrix<f64, N, N>) -> f64 {
    let d = b.diagonal().map(f64::abs);
    SMatrix::<f64, N, N>::from_fn(|i, j| (a - b)[(i, j)].abs() / (d[i] * d[j]).sqrt()).max()
}

#[test]
fn feedback_shares_out_the_fused_information() {
    let mut rng = ChaCha8Rng::seed_from_u64(8);
    let est = entry_estimates(&mut rng);
    let r = ci_fuse(&est, &[0.1, 0.2, 0.3, 0.4]).unwrap();
    let fb = feedback(&r);
    assert_eq!(fb.len(), 4);
    let mut info = SMatrix::<f64, 8, 8>::zeros();
    for ((x, p), w) in fb.iter().zip(&r.weights) {
        assert_eq!(*x, r.x);
        assert!(scaled_err(&(p * *w), &r.p) < 1e-14, "P⁺_i ≠ P_CI/ω_i");
        info += inv(p);
    }
    // eq. 22 shares the information out: Σ (P_CI/ω_i)⁻¹ = P_CI⁻¹.
    let e = scaled_err(&info, &inv(&r.p));
    assert!(e < 1e-8, "{e}");
    // Zero, negative and NaN weights are floored: finite, PD, P_CI / FEEDBACK_WEIGHT_FLOOR.
    let z = CiResult {
        x: r.x,
        p: r.p,
        weights: vec![0.0, -1.0, f64::NAN, 1.0, 2.0],
    };
    for (i, (x, p)) in feedback(&z).iter().enumerate() {
        assert!(x.iter().chain(p.iter()).all(|v| v.is_finite()) && p.cholesky().is_some());
        let expect = if i >= 3 {
            r.p
        } else {
            r.p / FEEDBACK_WEIGHT_FLOOR
        };
        assert!(scaled_err(p, &expect) < 1e-14, "weight {}", z.weights[i]);
    }
    // A genuinely zero weight from ci_fuse: the fused estimate is the remaining one.
    let r0 = ci_fuse(&est, &[0.0, 0.0, 0.0, 1.0]).unwrap();
    assert!(scaled_err(&r0.p, &est[3].1) < 1e-10);
    assert!(
        (r0.x - est[3].0)
            .component_div(&est[3].1.diagonal().map(f64::sqrt))
            .abs()
            .max()
            < 1e-10
    );
    assert!(
        feedback(&r0)
            .iter()
            .all(|(_, p)| p.iter().all(|v| v.is_finite()))
    );
}

#[test]
fn degenerate_sets_still_give_optimal_valid_weights() {
    // Duplicates, a linearly dependent member (flat objective directions) and one estimate
    // 10⁶ times better than the rest.
    let mut rng = ChaCha8Rng::seed_from_u64(21);
    for _ in 0..10 {
        let (p1, p2): (SMatrix<f64, 3, 3>, SMatrix<f64, 3, 3>) =
            (random_spd(&mut rng), random_spd(&mut rng));
        let mid = inv(&((inv(&p1) + inv(&p2)) * 0.5));
        let sets = [
            vec![p1, p2, p1, mid],
            vec![p1 * 1e-6, p2, mid, p1],
            vec![p1, p1, p1, p2],
        ];
        for ps in sets {
            let infos: Vec<_> = ps.iter().map(inv).collect();
            for (m, trace) in [
                (CiWeighting::OptimalTrace, true),
                (CiWeighting::OptimalDet, false),
            ] {
                let w = ci_weights(&infos, m).unwrap();
                assert!(
                    w.iter().all(|v| (0.0..=1.0).contains(v))
                        && (w.iter().sum::<f64>() - 1.0).abs() < 1e-12
                );
                let best = [
                    [1.0, 0.0, 0.0, 0.0],
                    [0.0, 1.0, 0.0, 0.0],
                    [0.5, 0.5, 0.0, 0.0],
                    [0.0, 0.0, 0.0, 1.0],
                ]
                .iter()
                .map(|g| objective(&ps, g, trace))
                .fold(f64::INFINITY, f64::min);
                assert!(
                    objective(&ps, &w, trace) <= best * (1.0 + 1e-10),
                    "{m:?}: {w:?}"
                );
            }
        }
    }
}

#[test]
fn bad_inputs_are_errors_not_panics() {
    let good = (Vector2::new(1.0, 2.0), Matrix2::identity());
    let empty: [(Vector2<f64>, Matrix2<f64>); 0] = [];
    let invalid = |r: Result<CiResult<2>, EstimationError>| {
        matches!(r, Err(EstimationError::InvalidInput(_)))
    };
    for m in METHODS {
        assert!(invalid(covariance_intersection(&empty, m)));
        assert!(ci_weights::<2>(&[], m).is_err());
        assert!(ci_weights(&[Matrix2::identity(), -Matrix2::identity()], m).is_err());
        assert!(ci_weights(&[Matrix2::identity(), Matrix2::new(1.0, 2.0, 2.0, 1.0)], m).is_err());
        assert!(ci_weights(&[Matrix2::identity() * f64::NAN], m).is_err());
        let not_pd = (Vector2::zeros(), Matrix2::new(1.0, 0.0, 0.0, 0.0));
        assert!(matches!(
            covariance_intersection(&[good, not_pd], m),
            Err(EstimationError::NotPositiveDefinite { .. })
        ));
        let nan_x = (Vector2::new(f64::NAN, 0.0), Matrix2::identity());
        assert!(matches!(
            covariance_intersection(&[good, nan_x], m),
            Err(EstimationError::NonFinite { .. })
        ));
        let zero_var = (Vector2::zeros(), Matrix2::new(1.0, 0.0, 0.0, 0.0));
        assert!(matches!(
            covariance_intersection(&[zero_var], m),
            Err(EstimationError::NotPositiveDefinite { .. })
        ));
        let inf_p = (Vector2::zeros(), Matrix2::identity() * f64::INFINITY);
        assert!(covariance_intersection(&[inf_p], m).is_err());
    }
    assert!(invalid(ci_fuse(&empty, &[])));
    assert!(invalid(ci_fuse(&[good, good], &[1.0])));
    assert!(invalid(ci_fuse(&[good], &[0.5, 0.5])));
    assert!(invalid(ci_fuse(&[good, good], &[1.5, -0.5])));
    assert!(invalid(ci_fuse(&[good, good], &[f64::NAN, 1.0])));
    assert!(invalid(ci_fuse(&[good, good], &[0.3, 0.3])));
    assert!(
        ci_fuse(
            &[good, (Vector2::zeros(), -Matrix2::identity())],
            &[1.0, 0.0]
        )
        .is_err()
    );
}
