//! Multiple-model banks: Gaussian log-likelihood, Magill's classical bank, seed 003's modified
//! mixture of experts (eq. 17–25) and the fusion of the bank's estimates.

use entrynav::estimation::EstimationError;
use entrynav::estimation::mmae::{
    ClassicBank, DEFAULT_ETA, DEFAULT_P_MIN, MixtureOfExperts, fuse_bank, gaussian_log_likelihood,
};
use nalgebra::{DMatrix, DVector, Matrix2, Matrix3, Vector2, Vector3};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

const LN_2PI: f64 = 1.837_877_066_409_345_5;

fn dv(v: &[f64]) -> DVector<f64> {
    DVector::from_vec(v.to_vec())
}

#[test]
fn log_likelihood_matches_closed_form_1d_and_3d() {
    let ll = gaussian_log_likelihood(&dv(&[1.3]), &DMatrix::from_element(1, 1, 0.7)).unwrap();
    let closed = -0.5 * (1.3 * 1.3 / 0.7 + 0.7f64.ln() + LN_2PI);
    assert!((ll - closed).abs() < 1e-12, "{ll} vs {closed}");

    let w: Matrix3<f64> = Matrix3::new(4.0, 1.2, -0.5, 1.2, 3.0, 0.4, -0.5, 0.4, 2.0);
    let e = Vector3::new(0.7, -1.1, 2.3);
    let closed =
        -0.5 * (e.dot(&(w.try_inverse().unwrap() * e)) + w.determinant().ln() + 3.0 * LN_2PI);
    let ll = gaussian_log_likelihood(
        &dv(e.as_slice()),
        &DMatrix::from_column_slice(3, 3, w.as_slice()),
    )
    .unwrap();
    assert!((ll - closed).abs() < 1e-12, "{ll} vs {closed}");

    // No measurement: density of "nothing observed" is 1.
    assert_eq!(
        gaussian_log_likelihood(&DVector::zeros(0), &DMatrix::zeros(0, 0)).unwrap(),
        0.0
    );
}

#[test]
fn huge_innovation_gives_finite_very_negative_log_likelihood() {
    let w = DMatrix::from_diagonal(&dv(&[1e-6, 2e-6]));
    let ll = gaussian_log_likelihood(&dv(&[1e6, -3e5]), &w).unwrap();
    assert!(ll.is_finite() && ll < -1e17, "{ll}");
    assert_eq!(ll.exp(), 0.0, "the density itself would underflow");
}

/// Draw ε ~ N(b, W) with W = L Lᵀ.
fn innovation(rng: &mut ChaCha8Rng, l: &Matrix2<f64>, bias: &Vector2<f64>) -> DVector<f64> {
    let n = Vector2::new(StandardNormal.sample(rng), StandardNormal.sample(rng));
    dv((l * n + bias).as_slice())
}

#[test]
fn classic_bank_identifies_the_unbiased_model() {
    let w = Matrix2::new(2.0, 0.3, 0.3, 1.0);
    let l = w.cholesky().unwrap().l();
    let wd = DMatrix::from_column_slice(2, 2, w.as_slice());
    let biases = [
        Vector2::new(1.5, 0.0),
        Vector2::zeros(),
        Vector2::new(-1.0, 1.0),
        Vector2::new(0.0, 1.2),
    ];
    let mut rng = ChaCha8Rng::seed_from_u64(3);
    let mut bank = ClassicBank::new(4, DEFAULT_P_MIN).unwrap();
    let mut first = None;
    for k in 1..=200 {
        // Model 2 (index 1) is the truth: its innovations are N(0, W); the others see the bias.
        let e = innovation(&mut rng, &l, &Vector2::zeros());
        let lls: Vec<f64> = biases
            .iter()
            .map(|b| gaussian_log_likelihood(&(&e - dv(b.as_slice())), &wd).unwrap())
            .collect();
        let p = bank.update(&lls).unwrap();
        assert!((p.iter().sum::<f64>() - 1.0).abs() < 1e-12);
        assert!(p.iter().all(|pi| *pi >= DEFAULT_P_MIN), "{p:?}");
        if first.is_none() && p[1] > 0.99 {
            first = Some(k);
        }
    }
    let first = first.expect("model 2 never reached 0.99");
    eprintln!(
        "classic bank: p(model 2) > 0.99 after {first} steps, final {:?}",
        bank.probs
    );
    assert!(first <= 40, "took {first} steps");
    assert!(bank.probs[1] > 0.99);
}

#[test]
fn identical_likelihoods_leave_probabilities_unchanged() {
    let mut bank = ClassicBank::new(4, 0.01).unwrap();
    bank.probs = vec![0.1, 0.2, 0.3, 0.4];
    for ll in [-3.2, -1e5, 40.0] {
        bank.update(&[ll; 4]).unwrap();
        for (p, q) in bank.probs.iter().zip([0.1, 0.2, 0.3, 0.4]) {
            assert!((p - q).abs() < 1e-15, "{:?}", bank.probs);
        }
    }
}

#[test]
fn floor_keeps_a_model_alive_and_zero_floor_lets_it_die() {
    let mut floored = ClassicBank::new(3, 0.01).unwrap();
    let mut bare = ClassicBank::new(3, 0.0).unwrap();
    for _ in 0..50 {
        floored.update(&[-1e4, 0.0, -1e4]).unwrap();
        bare.update(&[f64::NEG_INFINITY, 0.0, -1e4]).unwrap();
    }
    assert_eq!(floored.probs[0], 0.01);
    assert!((floored.probs[1] - 0.98).abs() < 1e-15);
    assert_eq!(bare.probs[0], 0.0);
    // Model 1 now explains the data: with the floor it returns within a few steps.
    for _ in 0..3 {
        floored.update(&[0.0, -10.0, -10.0]).unwrap();
    }
    assert!(floored.probs[0] > 0.97, "{:?}", floored.probs);
    // Without the floor the dead model stays dead; if every live model has zero likelihood → Err.
    bare.update(&[0.0, -10.0, -10.0]).unwrap();
    assert_eq!(bare.probs[0], 0.0);
    assert!(matches!(
        bare.update(&[0.0, f64::NEG_INFINITY, f64::NEG_INFINITY]),
        Err(EstimationError::InvalidInput(_))
    ));
}

#[test]
fn floor_water_fills_and_keeps_unit_sum() {
    // Equal likelihoods keep the prior; flooring 0.005 at 0.1 rescales the rest, which pushes
    // 0.105 under the floor too, so the remaining mass 0.8 is shared by 0.6 and 0.29.
    let mut bank = ClassicBank::new(4, 0.1).unwrap();
    bank.probs = vec![0.6, 0.105, 0.005, 0.29];
    let p = bank.update(&[-2.0; 4]).unwrap();
    assert_eq!((p[1], p[2]), (0.1, 0.1));
    assert!((p[0] - 0.6 * 0.8 / 0.89).abs() < 1e-15 && (p[3] - 0.29 * 0.8 / 0.89).abs() < 1e-15);
    assert!((p.iter().sum::<f64>() - 1.0).abs() < 1e-15);
}

#[test]
fn paper_scalar_normaliser_only_shifts_all_models_equally() {
    // Printed eq. 19 uses 1/√(2π|W|); the m-variate density has (2π)^{-m/2}|W|^{-1/2}. For m = 2
    // the two differ by the model-independent −½ ln 2π, so h (eq. 25) is unchanged.
    let w = DMatrix::from_diagonal(&dv(&[2.0, 3.0]));
    let ll = gaussian_log_likelihood(&dv(&[0.0, 0.0]), &w).unwrap();
    let printed = -0.5 * (LN_2PI + 6.0f64.ln());
    assert!((ll - (printed - 0.5 * LN_2PI)).abs() < 1e-14);
}

#[test]
fn gating_sums_to_one_and_ignores_a_common_shift() {
    let mut moe = MixtureOfExperts::new(3, 2, DEFAULT_ETA).unwrap();
    let z = dv(&[1.7, -0.4]);
    assert_eq!(moe.gating(&z).unwrap(), vec![1.0 / 3.0; 3]);
    moe.a = vec![dv(&[0.3, 1.0]), dv(&[-2.0, 0.5]), dv(&[1.1, -0.7])];
    let g = moe.gating(&z).unwrap();
    assert!((g.iter().sum::<f64>() - 1.0).abs() < 1e-15);
    // a_i + c shifts every u_i by zᵀc.
    let shifted = MixtureOfExperts {
        a: moe.a.iter().map(|a| a + dv(&[40.0, -7.0])).collect(),
        eta: DEFAULT_ETA,
    };
    for (x, y) in g.iter().zip(shifted.gating(&z).unwrap()) {
        assert!((x - y).abs() < 1e-14, "{x} vs {y}");
    }
}

#[test]
fn learning_rule_matches_eq_23_on_a_hand_example() {
    let mut moe = MixtureOfExperts {
        a: vec![dv(&[0.1, -0.2]), dv(&[0.3, 0.0])],
        eta: 0.5,
    };
    let z = dv(&[1.0, 2.0]);
    // u = (−0.3, 0.3) → g₁ = 1/(1 + e^0.6); p = (e^−1, e^−2.5) → h₁ = 1/(1 + e^−1.5 e^0.6).
    let (g, h) = moe.update(&z, &[-1.0, -2.5]).unwrap();
    let g1 = 1.0 / (1.0 + 0.6f64.exp());
    let h1 = 1.0 / (1.0 + (-0.9f64).exp());
    assert!((g[0] - g1).abs() < 1e-15 && (g[1] - (1.0 - g1)).abs() < 1e-15);
    assert!((h[0] - h1).abs() < 1e-15 && (h[1] - (1.0 - h1)).abs() < 1e-15);
    // eq. 23: a_i ← a_i + η (h_i − g_i) z.
    let d = 0.5 * (h1 - g1);
    let expect = [[0.1 + d, -0.2 + 2.0 * d], [0.3 - d, -2.0 * d]];
    for (a, e) in moe.a.iter().zip(expect) {
        assert!(
            (a[0] - e[0]).abs() < 1e-15 && (a[1] - e[1]).abs() < 1e-15,
            "{a} vs {e:?}"
        );
    }
    // Σ (h_i − g_i) = 0: the sum of the a_i is invariant.
    assert!(((&moe.a[0] + &moe.a[1]) - dv(&[0.4, -0.2])).amax() < 1e-15);
}

#[test]
fn moe_special_case_best_model_posterior_and_gating_tend_to_one() {
    // Seed 003 special case: seven density biases, truth Δ = 0.095, model 7 (Δ = 0.10) closest.
    let deltas = [-0.10, -0.06, -0.02, 0.0, 0.02, 0.06, 0.10];
    let lls: Vec<f64> = deltas
        .iter()
        .map(|d: &f64| -0.5 * ((d - 0.095) / 0.02).powi(2))
        .collect();
    // Normalised z = (q/P₀, a/g₀): dimensionless, order 1–10.
    let z = dv(&[5.0, 3.0, 1.0, 0.5]);
    let mut moe = MixtureOfExperts::new(7, 4, DEFAULT_ETA).unwrap();
    let (mut h_first, mut g_first, mut g_prev) = (None, None, 0.0);
    for k in 1..=100 {
        let (g, h) = moe.update(&z, &lls).unwrap();
        assert!(g[6] >= g_prev, "gating of the best model must not fall");
        g_prev = g[6];
        if h_first.is_none() && h[6] > 0.99 {
            h_first = Some(k);
        }
        if g_first.is_none() && g[6] > 0.99 {
            g_first = Some(k);
        }
    }
    let g = moe.gating(&z).unwrap();
    eprintln!(
        "MoE η = {DEFAULT_ETA}: h₇ > 0.99 at step {h_first:?}, g₇ > 0.99 at step {g_first:?}, final g₇ = {}",
        g[6]
    );
    assert!(h_first.unwrap() <= 20 && g_first.unwrap() <= 40);
    assert!(g[6] > 0.99 && g_prev > 0.99);
}

#[test]
fn moe_is_stable_for_huge_activations() {
    let mut moe = MixtureOfExperts {
        a: (0..4).map(|i| dv(&[1e5 * i as f64, -3e4])).collect(),
        eta: 1.0,
    };
    let z = dv(&[1e3, 2e3]);
    let g = moe.gating(&z).unwrap();
    assert!(g.iter().all(|x| x.is_finite()) && g[3] == 1.0 && g[0] == 0.0);
    // Model 1 has zero gating (ln g ≈ −3e8) and a much better likelihood: still no NaN.
    let (g, h) = moe.update(&z, &[0.0, -1e3, -1e4, -1e6]).unwrap();
    assert!(g.iter().chain(&h).all(|x| x.is_finite()));
    assert!((h.iter().sum::<f64>() - 1.0).abs() < 1e-12);
    assert!(moe.a.iter().all(|a| a.iter().all(|v| v.is_finite())));
    // Activations beyond f64 are reported, not propagated.
    let bad = MixtureOfExperts {
        a: vec![dv(&[1e300]), dv(&[0.0])],
        eta: 0.1,
    };
    assert!(matches!(
        bad.gating(&dv(&[1e300])),
        Err(EstimationError::NonFinite { .. })
    ));
}

#[test]
fn zero_slot_gives_no_learning_signal() {
    let mut moe = MixtureOfExperts::new(2, 3, 0.5).unwrap();
    moe.update(&dv(&[1.0, 0.0, 2.0]), &[0.0, -5.0]).unwrap();
    assert!(moe.a.iter().all(|a| a[1] == 0.0) && moe.a[0][0] > 0.0);
}

#[test]
fn fuse_single_weight_returns_that_estimate() {
    let est = [
        (Vector2::new(f64::NAN, 0.0), Matrix2::identity()), // diverged, zero weight → ignored
        (Vector2::new(3.0, -1.0), Matrix2::new(2.0, 0.5, 0.5, 1.0)),
        (Vector2::new(9.0, 9.0), Matrix2::identity() * 5.0),
    ];
    let (x, p) = fuse_bank(&[0.0, 1.0, 0.0], &est).unwrap();
    assert_eq!((x, p), est[1]);
}

#[test]
fn fuse_mixture_covariance_includes_spread_of_means() {
    let p2 = Matrix2::new(2.0, 0.5, 0.5, 1.0);
    let est = [
        (Vector2::zeros(), Matrix2::identity()),
        (Vector2::new(2.0, 1.0), p2),
    ];
    // By hand: x̄ = (1.5, 0.75); Σ wP = [[1.75, .375], [.375, 1]]; spread = [[.75, .375], [.375, .1875]].
    let (x, p) = fuse_bank(&[1.0, 3.0], &est).unwrap(); // weights renormalised to (¼, ¾)
    assert!((x - Vector2::new(1.5, 0.75)).amax() < 1e-15);
    assert!(
        (p - Matrix2::new(2.5, 0.75, 0.75, 1.1875)).amax() < 1e-15,
        "{p}"
    );
    let min_eig = |m: Matrix2<f64>| m.symmetric_eigenvalues().min();
    assert!(min_eig(p - Matrix2::identity() * 0.25) > 0.0);
    assert!(min_eig(p - p2 * 0.75) > 0.0);
    assert!(min_eig(p - Matrix2::identity() * 0.25 - p2 * 0.75) > -1e-14);
    assert!(
        p[(0, 0)] > 1.75,
        "larger than the weighted covariances alone"
    );
}

#[test]
fn bad_inputs_are_errors_not_panics() {
    use EstimationError::*;
    let w2 = DMatrix::identity(2, 2);
    assert!(matches!(
        gaussian_log_likelihood(&dv(&[1.0, 2.0, 3.0]), &w2),
        Err(InvalidInput(_))
    ));
    assert!(matches!(
        gaussian_log_likelihood(&dv(&[f64::NAN, 0.0]), &w2),
        Err(NonFinite { .. })
    ));
    let not_pd = DMatrix::from_row_slice(2, 2, &[1.0, 2.0, 2.0, 1.0]);
    assert!(matches!(
        gaussian_log_likelihood(&dv(&[1.0, 0.0]), &not_pd),
        Err(NotPositiveDefinite { .. })
    ));
    let asym = DMatrix::from_row_slice(2, 2, &[1.0, 0.5, 0.0, 1.0]);
    assert!(matches!(
        gaussian_log_likelihood(&dv(&[1.0, 0.0]), &asym),
        Err(InvalidInput(_))
    ));

    assert!(matches!(ClassicBank::new(0, 0.0), Err(InvalidInput(_))));
    assert!(matches!(ClassicBank::new(3, 0.5), Err(InvalidInput(_))));
    assert!(matches!(
        ClassicBank::new(3, f64::NAN),
        Err(InvalidInput(_))
    ));
    let mut bank = ClassicBank::new(3, 0.01).unwrap();
    assert!(matches!(bank.update(&[0.0, 0.0]), Err(InvalidInput(_))));
    assert!(matches!(
        bank.update(&[0.0, f64::NAN, 0.0]),
        Err(NonFinite { .. })
    ));
    assert!(matches!(
        bank.update(&[0.0, f64::INFINITY, 0.0]),
        Err(NonFinite { .. })
    ));
    assert_eq!(
        bank.probs,
        vec![1.0 / 3.0; 3],
        "failed updates leave the bank unchanged"
    );

    assert!(matches!(
        MixtureOfExperts::new(0, 2, 0.1),
        Err(InvalidInput(_))
    ));
    assert!(matches!(
        MixtureOfExperts::new(2, 0, 0.1),
        Err(InvalidInput(_))
    ));
    assert!(matches!(
        MixtureOfExperts::new(2, 2, -0.1),
        Err(InvalidInput(_))
    ));
    let mut moe = MixtureOfExperts::new(2, 2, 0.1).unwrap();
    assert!(matches!(moe.gating(&dv(&[1.0])), Err(InvalidInput(_))));
    assert!(matches!(
        moe.update(&dv(&[1.0, 2.0]), &[0.0]),
        Err(InvalidInput(_))
    ));
    assert!(matches!(
        moe.update(&dv(&[1.0, f64::NAN]), &[0.0, 0.0]),
        Err(NonFinite { .. })
    ));
    assert!(matches!(
        moe.update(&dv(&[1.0, 2.0]), &[f64::NAN, 0.0]),
        Err(NonFinite { .. })
    ));
    assert!(matches!(
        moe.update(&dv(&[1.0, 2.0]), &[f64::NEG_INFINITY; 2]),
        Err(InvalidInput(_))
    ));
    assert!(
        moe.a.iter().all(|a| a.amax() == 0.0),
        "failed updates do not learn"
    );

    let est = [
        (Vector2::zeros(), Matrix2::identity()),
        (Vector2::new(1.0, 0.0), Matrix2::identity()),
    ];
    assert!(matches!(fuse_bank(&[1.0], &est), Err(InvalidInput(_))));
    assert!(matches!(fuse_bank::<2>(&[], &[]), Err(InvalidInput(_))));
    assert!(matches!(fuse_bank(&[0.0, 0.0], &est), Err(InvalidInput(_))));
    assert!(matches!(
        fuse_bank(&[-0.5, 1.5], &est),
        Err(InvalidInput(_))
    ));
    assert!(matches!(
        fuse_bank(&[f64::NAN, 1.0], &est),
        Err(InvalidInput(_))
    ));
    let nan_est = [(Vector2::new(f64::NAN, 0.0), Matrix2::identity()), est[1]];
    assert!(matches!(
        fuse_bank(&[0.5, 0.5], &nan_est),
        Err(NonFinite { .. })
    ));
    let bad_p = [(Vector2::zeros(), -Matrix2::identity()), est[1]];
    assert!(matches!(
        fuse_bank(&[0.9, 0.1], &bad_p),
        Err(NotPositiveDefinite { .. })
    ));
}
