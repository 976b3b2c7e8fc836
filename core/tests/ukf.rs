//! Unscented (Schmidt–)Kalman filter behaviour, seed 001 §IV.B eq. 39–68: exactness on linear
//! systems, the consider update against the textbook Schmidt–Kalman filter, the benefit over
//! linearisation on a nonlinear map, and errors instead of panics.

use entrynav::estimation::EstimationError;
use entrynav::estimation::ukf::{SigmaPoints, Ukf, UkfParams, UkfWorkspace, unscented_transform};
use nalgebra::{DMatrix, DVector, Matrix2, Matrix3, SMatrix, SVector, Vector2, Vector3};
use proptest::prelude::*;
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

type M4 = SMatrix<f64, 4, 4>;
type V4 = SVector<f64, 4>;

fn max_abs<R: nalgebra::Dim, C: nalgebra::Dim, S: nalgebra::Storage<f64, R, C>>(
    m: &nalgebra::Matrix<f64, R, C, S>,
) -> f64 {
    m.iter().fold(0.0, |a, v| a.max(v.abs()))
}

/// A fixed linear-Gaussian problem: 4 states, 2 measurements.
struct Linear {
    f: M4,
    q: M4,
    h: SMatrix<f64, 2, 4>,
    r: Matrix2<f64>,
    x0: V4,
    p0: M4,
}

fn linear() -> Linear {
    let dt = 0.5;
    #[rustfmt::skip]
    let f = M4::new(
        1.0, 0.0, dt, 0.0,
        0.0, 1.0, 0.0, dt,
        0.0, 0.0, 1.0, 0.1,
        0.0, 0.0, -0.1, 1.0,
    );
    #[rustfmt::skip]
    let a = M4::new(
        1.0, 0.2, 0.0, 0.1,
        0.0, 2.0, 0.3, 0.0,
        0.4, 0.0, 0.5, 0.0,
        0.0, 0.1, 0.2, 0.7,
    );
    let h = SMatrix::<f64, 2, 4>::new(1.0, 0.5, 0.0, 0.0, 0.0, 1.0, 0.3, -0.2);
    Linear {
        f,
        q: M4::from_diagonal(&V4::new(0.01, 0.02, 0.003, 0.004)),
        h,
        r: Matrix2::new(0.3, 0.05, 0.05, 0.2),
        x0: V4::new(10.0, -3.0, 1.5, 0.7),
        p0: a * a.transpose(),
    }
}

fn dv2(v: Vector2<f64>) -> DVector<f64> {
    DVector::from_column_slice(v.as_slice())
}

/// Exact Kalman filter for `linear()`, compared with the UKF over three predict/update cycles.
fn ukf_matches_kalman(params: UkfParams, tol: f64) -> Result<f64, String> {
    let s = linear();
    let (mut x, mut p) = (s.x0, s.p0);
    let mut ukf = Ukf::new(s.x0, s.p0, params, 0).map_err(|e| e.to_string())?;
    let mut worst = 0.0f64;
    for k in 0..3 {
        let z = Vector2::new(10.0 + k as f64, -2.0 + 0.5 * k as f64);
        x = s.f * x;
        p = s.f * p * s.f.transpose() + s.q;
        let sk = s.h * p * s.h.transpose() + s.r;
        let kk = p * s.h.transpose() * sk.try_inverse().unwrap();
        let nu = z - s.h * x;
        let nis = nu.dot(&(sk.try_inverse().unwrap() * nu));
        x += kk * nu;
        p -= kk * sk * kk.transpose();
        ukf.predict(|v| s.f * v, &s.q).map_err(|e| e.to_string())?;
        let r = DMatrix::from_column_slice(2, 2, s.r.as_slice());
        let u = ukf
            .update(|v| dv2(s.h * v), &dv2(z), &r)
            .map_err(|e| e.to_string())?;
        let errs = [
            max_abs(&(ukf.x - x)),
            max_abs(&(ukf.p - p)),
            max_abs(&(u.s - DMatrix::from_column_slice(2, 2, sk.as_slice()))),
            max_abs(&(u.innovation - dv2(nu))),
            (u.nis - nis).abs(),
        ];
        if !errs.iter().all(|e| e.is_finite() && *e < tol) {
            return Err(format!("{params:?} cycle {k}: errors {errs:?}"));
        }
        worst = errs.iter().fold(worst, |a, e| a.max(*e));
    }
    Ok(worst)
}

#[test]
fn linear_gaussian_ukf_equals_the_exact_kalman_filter() {
    for params in [
        UkfParams::SEED001,
        UkfParams::new(1.0, 0.0, Some(0.0)),
        UkfParams::new(0.5, 2.0, Some(-3.0)),
        UkfParams::new(0.1, 2.0, None),
    ] {
        let worst = ukf_matches_kalman(params, 1e-10).unwrap();
        println!("{params:?}: max |UKF − KF| = {worst:.1e}");
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 64, failure_persistence: None, ..ProptestConfig::default() })]
    #[test]
    fn linear_exactness_for_any_valid_constants(
        alpha in 0.05f64..=1.0, beta in 0.0f64..4.0, kappa in -3.5f64..5.0,
    ) {
        let r = ukf_matches_kalman(UkfParams::new(alpha, beta, Some(kappa)), 1e-10);
        prop_assert!(r.is_ok(), "{:?}", r);
    }
}

#[test]
fn sigma_points_reproduce_mean_and_covariance() {
    let s = linear();
    let sp = SigmaPoints::draw(&s.x0, &s.p0, &UkfParams::SEED001).unwrap();
    assert_eq!(sp.points.len(), 9);
    assert!((sp.wm.iter().sum::<f64>() - 1.0).abs() < 1e-14);
    assert!((sp.wc.iter().sum::<f64>() - 3.0).abs() < 1e-14); // Σ w_c = 1 + 1 − α² + β
    let naive_mean: V4 = sp.points.iter().zip(&sp.wm).map(|(x, w)| x * *w).sum();
    assert!(max_abs(&(naive_mean - s.x0)) < 1e-12);
    assert!(max_abs(&(sp.covariance(&sp.mean()) - s.p0)) < 1e-12);
    let ut = unscented_transform(&sp, |x| s.h * x).unwrap();
    assert!(max_abs(&(ut.mean - s.h * s.x0)) < 1e-12);
    assert!(max_abs(&(ut.cov - s.h * s.p0 * s.h.transpose())) < 1e-12);
    assert!(max_abs(&(ut.cross - s.p0 * s.h.transpose())) < 1e-12);
}

/// Polar (r, θ) → Cartesian, the classic case where linearisation biases the mean.
#[test]
fn polar_to_cartesian_mean_beats_linearisation() {
    let (x0, sr, st) = (Vector2::new(1.0, std::f64::consts::FRAC_PI_2), 0.02, 0.35);
    let p0 = Matrix2::new(sr * sr, 0.0, 0.0, st * st);
    let polar = |x: &Vector2<f64>| Vector2::new(x[0] * x[1].cos(), x[0] * x[1].sin());
    let mut rng = ChaCha8Rng::seed_from_u64(2024);
    let n = 200_000;
    let (mut mc, mut m2) = (Vector2::zeros(), Vector2::zeros());
    for _ in 0..n {
        let (a, b): (f64, f64) = (
            StandardNormal.sample(&mut rng),
            StandardNormal.sample(&mut rng),
        );
        let y = polar(&(x0 + Vector2::new(sr * a, st * b)));
        mc += y / n as f64;
        m2 += y.component_mul(&y) / n as f64;
    }
    let se = ((m2 - mc.component_mul(&mc)) / n as f64)
        .map(f64::sqrt)
        .norm();
    let mut ukf = Ukf::new(x0, p0, UkfParams::SEED001, 0).unwrap();
    let r = DMatrix::identity(2, 2) * 1e-4;
    let u = ukf
        .update(|x| dv2(polar(x)), &dv2(Vector2::new(0.0, 1.0)), &r)
        .unwrap();
    let (ukf_err, lin_err) = ((&u.predicted - dv2(mc)).norm(), (polar(&x0) - mc).norm());
    println!("MC mean {mc:?} ± {se:.1e}: UKF error {ukf_err:.2e}, linearised error {lin_err:.2e}");
    assert!(ukf_err < 5.0 * se + 1e-4, "UKF mean off by {ukf_err}");
    assert!(lin_err > 0.05 && ukf_err < lin_err / 20.0);
    // The same transform through `predict` (f = polar map) gives the same mean.
    let mut g = Ukf::new(x0, p0, UkfParams::SEED001, 0).unwrap();
    g.predict(polar, &(Matrix2::identity() * 1e-9)).unwrap();
    assert!((g.x - Vector2::new(u.predicted[0], u.predicted[1])).norm() < 1e-12);
    // Exact mean: r̄ e^{−σθ²/2} along y.
    assert!((g.x[1] - (-st * st / 2.0).exp()).abs() < 1e-4);
}

/// Consider problem: x = (position, velocity), c = a bias; z = [p + c, v].
struct Consider {
    f: Matrix3<f64>,
    q: Matrix3<f64>,
    h: SMatrix<f64, 2, 3>,
    r: Matrix2<f64>,
}

fn consider() -> Consider {
    let dt = 1.0;
    Consider {
        f: Matrix3::new(1.0, dt, 0.5 * dt, 0.0, 1.0, dt, 0.0, 0.0, 0.95),
        q: Matrix3::from_diagonal(&Vector3::new(1e-3, 1e-3, 1e-3)),
        h: SMatrix::<f64, 2, 3>::new(1.0, 0.0, 1.0, 0.0, 1.0, 0.3),
        r: Matrix2::new(0.5, 0.0, 0.0, 0.1),
    }
}

/// Textbook linear Schmidt–Kalman update (x = first 2 states, c = the last).
fn schmidt_kf(x: &mut Vector3<f64>, p: &mut Matrix3<f64>, c: &Consider, z: Vector2<f64>) {
    let (hx, hc) = (c.h.fixed_columns::<2>(0), c.h.fixed_columns::<1>(2));
    let (pxx, pxc, pcc) = (
        p.fixed_view::<2, 2>(0, 0),
        p.fixed_view::<2, 1>(0, 2),
        p[(2, 2)],
    );
    let s = c.h * *p * c.h.transpose() + c.r;
    let kx = (pxx * hx.transpose() + pxc * hc.transpose()) * s.try_inverse().unwrap();
    let nu = z - c.h * *x;
    let new_pxx = pxx - kx * s * kx.transpose();
    let new_pxc = pxc - kx * (hx * pxc + hc * pcc);
    let mut xx = x.fixed_rows_mut::<2>(0);
    xx += kx * nu;
    p.fixed_view_mut::<2, 2>(0, 0).copy_from(&new_pxx);
    p.fixed_view_mut::<2, 1>(0, 2).copy_from(&new_pxc);
    p.fixed_view_mut::<1, 2>(2, 0)
        .copy_from(&new_pxc.transpose());
}

#[test]
fn schmidt_consider_update_matches_the_textbook_form_and_is_conservative() {
    let c = consider();
    let x0 = Vector3::new(100.0, -5.0, 0.0);
    let p0 = Matrix3::new(4.0, 0.5, 0.3, 0.5, 1.0, 0.1, 0.3, 0.1, 0.8);
    let mut sk = Ukf::new(x0, p0, UkfParams::SEED001, 1).unwrap();
    let mut full = Ukf::new(x0, p0, UkfParams::SEED001, 0).unwrap();
    let (mut xt, mut pt) = (x0, p0);
    let r = DMatrix::from_column_slice(2, 2, c.r.as_slice());
    let mut worst = 0.0f64;
    for k in 0..25 {
        let z = Vector2::new(100.0 - 5.0 * k as f64 + 0.7, -5.0 + 0.1 * (k % 3) as f64);
        for f in [&mut sk, &mut full] {
            f.predict(|v| c.f * v, &c.q).unwrap();
        }
        (xt, pt) = (c.f * xt, c.f * pt * c.f.transpose() + c.q);
        let prior = sk.clone();
        let u = sk.update(|v| dv2(c.h * v), &dv2(z), &r).unwrap();
        full.update(|v| dv2(c.h * v), &dv2(z), &r).unwrap();
        schmidt_kf(&mut xt, &mut pt, &c, z);
        worst = worst.max(max_abs(&(sk.x - xt))).max(max_abs(&(sk.p - pt)));
        // eq. 67–68: ĉ and P_cc untouched; P_xc⁺ = P_xc − K_x S K_cᵀ.
        assert_eq!(sk.x[2], prior.x[2]);
        assert_eq!(sk.p[(2, 2)], prior.p[(2, 2)]);
        let ph = prior.p * c.h.transpose();
        let s_mat = c.h * prior.p * c.h.transpose() + c.r;
        let kk = ph * s_mat.try_inverse().unwrap();
        let (kx, kc) = (kk.fixed_rows::<2>(0), kk.fixed_rows::<1>(2));
        let pxc = prior.p.fixed_view::<2, 1>(0, 2) - kx * s_mat * kc.transpose();
        assert!(max_abs(&(sk.p.fixed_view::<2, 1>(0, 2) - pxc)) < 1e-10);
        assert!(max_abs(&(DMatrix::from_column_slice(2, 2, s_mat.as_slice()) - u.s)) < 1e-10);
        // The consider filter takes no credit for learning c: P_xx(consider) ⪰ P_xx(full).
        let d = sk.p.fixed_view::<2, 2>(0, 0) - full.p.fixed_view::<2, 2>(0, 0);
        assert!(d.symmetric_eigenvalues().min() > -1e-10, "step {k}: {d}");
    }
    println!("Schmidt UKF vs textbook: max |Δ| = {worst:.2e}");
    assert!(worst < 1e-10);
    let d = sk.p.fixed_view::<2, 2>(0, 0) - full.p.fixed_view::<2, 2>(0, 0);
    assert!(
        d.trace() > 1e-3,
        "consider P_xx should be strictly larger: {d}"
    );
}

#[test]
fn errors_not_panics() {
    let s = linear();
    let err = Ukf::new(s.x0, -s.p0, UkfParams::SEED001, 0).unwrap_err();
    assert!(matches!(err, EstimationError::NotPositiveDefinite { .. }));
    let mut f = Ukf::new(s.x0, s.p0, UkfParams::SEED001, 0).unwrap();
    let before = f.clone();
    let nan_f = |v: &V4| {
        if v[0] > s.x0[0] {
            V4::repeat(f64::NAN)
        } else {
            *v
        }
    };
    let e = f.predict(nan_f, &s.q).unwrap_err();
    assert!(matches!(e, EstimationError::NonFinite { .. }), "{e}");
    assert!(f.predict(|v| *v, &(s.q * f64::INFINITY)).is_err());
    assert!(matches!(
        f.predict(|v| *v, &(-s.p0 * 2.0)),
        Err(EstimationError::NotPositiveDefinite { .. })
    ));
    let z = DVector::from_element(2, 1.0);
    let r = DMatrix::identity(2, 2);
    let nan_h = |v: &V4| DVector::from_element(2, if v[1] < s.x0[1] { f64::NAN } else { 0.0 });
    assert!(matches!(
        f.update(nan_h, &z, &r),
        Err(EstimationError::NonFinite { .. })
    ));
    let short = |_: &V4| DVector::zeros(1);
    assert!(matches!(
        f.update(short, &z, &r),
        Err(EstimationError::InvalidInput(_))
    ));
    let r3 = DMatrix::identity(3, 3);
    assert!(matches!(
        f.update(|v| dv2(s.h * v), &z, &r3),
        Err(EstimationError::InvalidInput(_))
    ));
    let neg = -DMatrix::identity(2, 2) * 1e3;
    assert!(matches!(
        f.update(|v| dv2(s.h * v), &z, &neg),
        Err(EstimationError::NotPositiveDefinite { .. })
    ));
    assert_eq!(f, before, "a failed step leaves the filter unchanged");
}

#[test]
fn invalid_constants_and_consider_count_are_rejected() {
    let s = linear();
    let bad = [
        UkfParams::new(0.0, 2.0, None),
        UkfParams::new(1.5, 2.0, None),
        UkfParams::new(f64::NAN, 2.0, None),
        UkfParams::new(1.0, 2.0, Some(-4.0)), // L + κ = 0
        UkfParams::new(1.0, f64::INFINITY, None),
    ];
    for params in bad {
        let e = Ukf::new(s.x0, s.p0, params, 0).unwrap_err();
        assert!(matches!(e, EstimationError::InvalidInput(_)), "{params:?}");
    }
    assert!(Ukf::new(s.x0, s.p0, UkfParams::SEED001, 4).is_err());
    assert!(Ukf::new(s.x0, s.p0, UkfParams::SEED001, 3).is_ok());
}

#[test]
fn empty_measurement_is_a_no_op() {
    let s = linear();
    let mut f = Ukf::new(s.x0, s.p0, UkfParams::SEED001, 0).unwrap();
    let before = f.clone();
    let (z, r) = (DVector::zeros(0), DMatrix::zeros(0, 0));
    let u = f.update(|_| DVector::zeros(0), &z, &r).unwrap();
    assert_eq!((u.nis, u.innovation.len()), (0.0, 0));
    assert_eq!(f, before);
}

/// f or h = (x − x̂)ᵀP⁻¹(x − x̂) puts every non-central sigma point at the same value: with β < α² and
/// w_m⁽⁰⁾ < 0 the weighted covariance is then negative (g < 0, see the module docs).
#[test]
fn negative_central_weight_can_lose_pd_only_when_beta_below_alpha_squared() {
    let s = linear();
    let pinv = s.p0.try_inverse().unwrap();
    let maha = move |v: &V4| (v - s.x0).dot(&(pinv * (v - s.x0)));
    let radial = |v: &V4| V4::new(maha(v), v[1], v[2], v[3]);
    let bad = UkfParams::new(1.0, 0.0, None); // w_m⁽⁰⁾ = w_c⁽⁰⁾ = −1/3
    let mut f = Ukf::new(s.x0, s.p0, bad, 0).unwrap();
    let e = f.predict(radial, &(M4::identity() * 1e-6)).unwrap_err();
    assert!(
        matches!(e, EstimationError::NotPositiveDefinite { .. }),
        "{e}"
    );
    let z = DVector::from_element(1, 0.0);
    let r = DMatrix::identity(1, 1) * 1e-6;
    let hr = |v: &V4| DVector::from_element(1, maha(v));
    assert!(matches!(
        f.update(hr, &z, &r),
        Err(EstimationError::NotPositiveDefinite { .. })
    ));
    // Seed 001's α = 1, β = 2: the same maps are fine.
    let mut g = Ukf::new(s.x0, s.p0, UkfParams::SEED001, 0).unwrap();
    g.predict(radial, &(M4::identity() * 1e-6)).unwrap();
    g.update(hr, &z, &r).unwrap();
}

/// `A Aᵀ + shift·I`: positive definite for shift > 0, possibly indefinite below.
fn gram(v: &[f64], shift: f64) -> M4 {
    let a = M4::from_column_slice(v);
    a * a.transpose() + M4::identity() * shift
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 512, failure_persistence: None, ..ProptestConfig::default() })]
    /// Random (possibly indefinite) covariances, noises, constants and maps: Ok with a
    /// symmetric positive-definite P, or an error — never a panic.
    #[test]
    fn random_inputs_never_panic(
        p in prop::collection::vec(-3.0f64..3.0, 16),
        q in prop::collection::vec(-0.3f64..0.3, 16),
        shifts in (-0.3f64..1.0, -0.01f64..0.05),
        r in prop::collection::vec(-0.2f64..1.0, 4),
        alpha in -0.2f64..1.2, beta in -1.0f64..3.0, kappa in prop::option::of(-5.0f64..4.0),
        nc in 0usize..5, scale in prop::sample::select(vec![1.0, 1.0, 1.0, 1e8, f64::NAN, f64::INFINITY]),
    ) {
        let params = UkfParams::new(alpha, beta, kappa);
        let Ok(mut f) = Ukf::new(V4::repeat(1.0), gram(&p, shifts.0), params, nc) else { return Ok(()) };
        let step = |v: &V4| V4::new(v[0] * v[1], v[1].sin() * scale, v[2], v[3].exp().min(1e300));
        let pd = |m: &M4| m.cholesky().is_some() && *m == m.transpose();
        if f.predict(step, &gram(&q, shifts.1)).is_ok() {
            prop_assert!(pd(&f.p));
        }
        let r = DMatrix::from_column_slice(2, 2, &r);
        let z = DVector::from_element(2, 0.5);
        let mut ws = UkfWorkspace::default();
        let h = |v: &V4, out: &mut [f64]| {
            out[0] = v[0] * scale;
            out[1] = v[1].atan2(v[2]);
            Ok(())
        };
        if f.update_with(&mut ws, h, &z, &r).is_ok() {
            prop_assert!(pd(&f.p) && f.x.iter().all(|v| v.is_finite()));
        }
    }

    /// With β ≥ α², P ≻ 0, Q ⪰ 0 and R ≻ 0 every step succeeds for any smooth nonlinear f, h,
    /// consider or not (module docs: the UT covariances are then positive semidefinite).
    #[test]
    fn valid_constants_and_noises_never_lose_positive_definiteness(
        p in prop::collection::vec(-2.0f64..2.0, 16),
        r in prop::collection::vec(-1.0f64..1.0, 4),
        alpha in 0.2f64..=1.0, db in 0.0f64..3.0, kappa in -3.0f64..3.0, nc in 0usize..4,
    ) {
        let params = UkfParams::new(alpha, alpha * alpha + db, Some(kappa));
        let mut f = Ukf::new(V4::repeat(0.5), gram(&p, 0.05), params, nc).unwrap();
        let step = |v: &V4| {
            let (a, b, c, d) = (v[0], v[1], v[2], v[3]);
            V4::new(0.9 * a + 0.3 * b.sin(), 0.8 * b + 0.2 * a * d.tanh(), c.tanh() + 0.1 * c * c, 0.95 * d + 0.1 * a.cos())
        };
        let h = |v: &V4| DVector::from_vec(vec![v[1].atan2(v[2] + 3.0), v[0] * v[3], v.norm()]);
        let a = DMatrix::from_column_slice(2, 2, &r);
        let mut rr = DMatrix::identity(3, 3) * 0.01;
        rr.view_mut((0, 0), (2, 2)).copy_from(&(&a * a.transpose()));
        for k in 0..5 {
            f.predict(step, &(M4::identity() * 1e-6)).unwrap();
            let z = DVector::from_element(3, 0.1 * k as f64);
            let u = f.update(h, &z, &rr);
            prop_assert!(u.is_ok(), "step {}: {:?}", k, u);
        }
    }

    /// With β ≥ α² (seed 001: α = 1, β = 2) the predicted covariance minus Q is positive
    /// semidefinite for any map even when w_c⁽⁰⁾ < 0 (L = 12 here).
    #[test]
    fn beta_at_least_alpha_squared_keeps_the_ut_covariance_psd(
        a in prop::collection::vec(-2.0f64..2.0, 12), b in -3.0f64..3.0,
    ) {
        let x0 = SVector::<f64, 12>::from_column_slice(&a);
        let mut f = Ukf::new(x0, SMatrix::identity(), UkfParams::SEED001, 0).unwrap();
        assert!(UkfParams::SEED001.weights_for(12).unwrap().1 < 0.0);
        let map = |v: &SVector<f64, 12>| v.map(|e| (b * e).sin() + e * e) * v.norm();
        let q = SMatrix::<f64, 12, 12>::identity() * 1e-9;
        f.predict(map, &q).unwrap();
        let min = (f.p - q).symmetric_eigenvalues().min();
        prop_assert!(min > -1e-9 * max_abs(&f.p), "min eigenvalue {min}");
    }
}

/// The allocation-light workspace path (`predict_with` / `update_with`, what the navigation
/// filters use) gives the same result as the allocating `predict` / `update` over repeated steps
/// with N = 8 and 7 measurements. (Its speed is measured by the `filters` criterion benchmark.)
#[test]
fn workspace_path_matches_the_allocating_path() {
    type V8 = SVector<f64, 8>;
    let x0 = V8::from_fn(|i, _| 1.0 + i as f64);
    let p0 = SMatrix::<f64, 8, 8>::identity() * 0.1;
    let q = SMatrix::<f64, 8, 8>::identity() * 1e-4;
    let f = |v: &V8| V8::from_fn(|i, _| v[i] + 0.01 * v[(i + 1) % 8]);
    let hm = |v: &V8, out: &mut [f64]| {
        for (j, o) in out.iter_mut().enumerate() {
            *o = (v[j] * v[j + 1]).sqrt();
        }
        Ok(())
    };
    let h = |v: &V8| DVector::from_fn(7, |j, _| (v[j] * v[j + 1]).sqrt());
    let r = DMatrix::identity(7, 7) * 1e-2;
    let mut a = Ukf::new(x0, p0, UkfParams::SEED001, 1).unwrap();
    let mut b = a.clone();
    let mut ws = UkfWorkspace::default();
    for k in 0..50 {
        let z = DVector::from_fn(7, |j, _| {
            ((1.0 + j as f64) * (2.0 + j as f64)).sqrt() * (1.0 + 0.01 * (k as f64).sin())
        });
        a.predict(f, &q).unwrap();
        let ua = a.update(h, &z, &r).unwrap();
        b.predict_with(&mut ws, f, &q).unwrap();
        let ub = b.update_with(&mut ws, hm, &z, &r).unwrap();
        let scale = a.p.abs().max();
        assert!(
            (a.x - b.x).abs().max() <= 1e-12 * a.x.abs().max(),
            "step {k}: x differs"
        );
        assert!(
            (a.p - b.p).abs().max() <= 1e-12 * scale,
            "step {k}: P differs"
        );
        assert!(
            (ua.nis - ub.nis).abs() <= 1e-9 * ua.nis.abs().max(1.0),
            "step {k}: NIS differs"
        );
    }
}
