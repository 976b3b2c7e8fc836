//! Consistency building blocks against closed forms: the Schmidt consider EKF against the
//! textbook Schmidt–Kalman equations, and bias states on a linear-Gaussian toy where the Kalman
//! filter is exact (its NEES must sit in the χ² band and it must recover the bias).

use entrynav::estimation::ekf::Ekf;
use entrynav::sim::nees_bounds_95;
use nalgebra::{SMatrix, SVector};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

type M5 = SMatrix<f64, 5, 5>;
type V5 = SVector<f64, 5>;

fn spd5(seed: f64) -> M5 {
    let a = M5::from_fn(|r, c| ((r * 5 + c) as f64 * seed).sin());
    a * a.transpose() + M5::identity() * 0.4
}

/// Schmidt–Kalman (Tapley, Schutz & Born §6.4; Woodbury, Schmidt 1966) for states x (first 3)
/// and consider parameters c (last 2) and a scalar measurement z = h·[x; c] + v:
/// K_x = (P_xx h_xᵀ + P_xc h_cᵀ)/s, s = h P hᵀ + r;
/// P_xx⁺ = P_xx − K_x s K_xᵀ, P_xc⁺ = P_xc − K_x (h P)_c, P_cc⁺ = P_cc, x̂_c unchanged.
#[test]
fn consider_ekf_equals_the_textbook_schmidt_kalman_form() {
    for (k, seed) in [0.7, 1.3, 2.9].into_iter().enumerate() {
        let p = spd5(seed);
        let x0 = V5::from_fn(|i, _| (i as f64 + 1.0) * 0.1 * (k as f64 + 1.0));
        let h = V5::from_fn(|i, _| ((i + k) as f64 * 0.77).cos());
        let (z, r) = (0.8, 0.3);
        let mut f = Ekf::new(x0, p).unwrap().with_consider(2).unwrap();
        f.update_scalar(h.dot(&x0), &h, z, r).unwrap();
        // Textbook.
        let ph = p * h;
        let s = h.dot(&ph) + r;
        let kx = ph.fixed_rows::<3>(0) / s;
        let nu = z - h.dot(&x0);
        let mut x_exp = x0;
        for i in 0..3 {
            x_exp[i] += kx[i] * nu;
        }
        let mut p_exp = p;
        for i in 0..3 {
            for j in 0..3 {
                p_exp[(i, j)] = p[(i, j)] - kx[i] * s * kx[j];
            }
            for j in 3..5 {
                let v = p[(i, j)] - kx[i] * ph[j];
                p_exp[(i, j)] = v;
                p_exp[(j, i)] = v;
            }
        }
        assert!((f.x - x_exp).abs().max() < 1e-12, "case {k}: x");
        assert!(
            (f.p - p_exp).abs().max() < 1e-12,
            "case {k}: P {}",
            f.p - p_exp
        );
        // The consider block and estimate are untouched; a plain EKF would update them.
        assert_eq!(f.p.fixed_view::<2, 2>(3, 3), p.fixed_view::<2, 2>(3, 3));
        assert_eq!(f.x.fixed_rows::<2>(3), x0.fixed_rows::<2>(3));
        let mut plain = Ekf::new(x0, p).unwrap();
        plain.update_scalar(h.dot(&x0), &h, z, r).unwrap();
        assert!((plain.p - f.p).abs().max() > 1e-3);
    }
    assert!(
        Ekf::new(V5::zeros(), M5::identity())
            .unwrap()
            .with_consider(5)
            .is_err()
    );
}

/// A spring with an accelerometer: x = [position, velocity, bias], ẋ = v, v̇ = −ω²x, ḃ = 0, with
/// a position fix z₁ = x + n₁ and an accelerometer z₂ = −ω²x + b + n₂. Linear and Gaussian, so
/// the Kalman filter (our EKF on the exact transition matrix) is the optimal filter: over a Monte
/// Carlo its NEES is χ²(3) and the bias estimate converges to the truth.
#[test]
fn bias_states_recover_a_constant_bias_on_a_linear_gaussian_toy() {
    type M3 = SMatrix<f64, 3, 3>;
    type V3 = SVector<f64, 3>;
    let (w2, dt) = (0.04f64, 1.0);
    let w = w2.sqrt();
    // Exact transition of the oscillator over dt; the bias is constant.
    let (c, s) = ((w * dt).cos(), (w * dt).sin());
    let phi = M3::new(c, s / w, 0.0, -w * s, c, 0.0, 0.0, 0.0, 1.0);
    let (r1, r2) = (0.5f64.powi(2), 0.01f64.powi(2));
    let p0 = M3::from_diagonal(&V3::new(4.0, 0.25, 0.05f64.powi(2)));
    let true_bias = -0.03;
    let (runs, steps) = (400, 120);
    let mut nees_sum = vec![0.0; steps];
    let mut final_err = Vec::new();
    let mut rng = ChaCha8Rng::seed_from_u64(5);
    let mut z = || -> f64 { StandardNormal.sample(&mut rng) };
    for _ in 0..runs {
        let mut truth = V3::new(2.0 * z(), 0.5 * z(), true_bias);
        let mut f = Ekf::new(V3::new(0.0, 0.0, 0.0), p0).unwrap();
        // The filter's prior: truth drawn from N(x̂0, P0) except the bias, a fixed constant the
        // prior covers (0.6σ): consistency must still hold in the mean.
        for (k, sum) in nees_sum.iter_mut().enumerate() {
            truth = phi * truth;
            f.predict(phi * f.x, &phi, &M3::zeros()).unwrap();
            let h1 = V3::new(1.0, 0.0, 0.0);
            let h2 = V3::new(-w2, 0.0, 1.0);
            let z1 = truth[0] + r1.sqrt() * z();
            let z2 = -w2 * truth[0] + truth[2] + r2.sqrt() * z();
            f.update_scalar(h1.dot(&f.x), &h1, z1, r1).unwrap();
            f.update_scalar(h2.dot(&f.x), &h2, z2, r2).unwrap();
            let e = f.x - truth;
            *sum += e.dot(&(f.p.try_inverse().unwrap() * e));
            if k + 1 == steps {
                final_err.push((e[2], f.p[(2, 2)].sqrt()));
            }
        }
    }
    // The bias is recovered: the final errors are small against the prior σ and inside 3σ.
    let rms = (final_err.iter().map(|(e, _)| e * e).sum::<f64>() / runs as f64).sqrt();
    let sigma = final_err[0].1;
    assert!(rms < 0.1 * 0.05, "bias RMS error {rms} vs prior sigma 0.05");
    assert!(
        (rms / sigma - 1.0).abs() < 0.15,
        "RMS {rms} vs filter sigma {sigma}"
    );
    // The per-epoch mean NEES over runs sits in its χ² 95 % band (runs are independent; epochs of
    // one run are not, so the band is the per-epoch one), and so does its time average.
    let (lo, hi) = nees_bounds_95(3, runs);
    let means: Vec<f64> = nees_sum.iter().map(|s| s / runs as f64).collect();
    let inside = means.iter().filter(|m| (lo..=hi).contains(*m)).count();
    assert!(
        inside * 10 >= steps * 9,
        "{inside} of {steps} epochs in [{lo}, {hi}]: {means:?}"
    );
    let anees = means.iter().sum::<f64>() / steps as f64;
    assert!(
        anees > lo && anees < hi,
        "ANEES {anees} outside [{lo}, {hi}]"
    );
}
