//! LinCov of a linear Kalman filter (issue 25's first acceptance check): matched to the truth, it
//! reproduces the filter's own P exactly; with a wrong Q, a wrong R and a wrong start it predicts
//! the error statistics a 20,000-run Monte Carlo of our EKF code measures, within the Monte
//! Carlo's sampling interval.

use entrynav::estimation::ekf::Ekf;
use entrynav::lincov::{LinearFilterModel, LinearLinCov, LinearTruthModel};
use nalgebra::{Matrix1, Matrix2, SMatrix, Vector2};
use rand::SeedableRng;
use rand_chacha::ChaCha8Rng;
use rand_distr::{Distribution, StandardNormal};

const DT: f64 = 1.0;
const EPOCHS: usize = 40;

/// A constant-velocity target with white-noise acceleration, position measured.
fn truth() -> LinearTruthModel<2, 1> {
    let q = 0.05;
    LinearTruthModel {
        f: Matrix2::new(1.0, DT, 0.0, 1.0),
        h: SMatrix::<f64, 1, 2>::new(1.0, 0.0),
        q: Matrix2::new(DT.powi(3) / 3.0, DT * DT / 2.0, DT * DT / 2.0, DT) * q,
        r: Matrix1::new(4.0),
        m0: Vector2::new(0.0, 1.0),
        p0: Matrix2::new(25.0, 0.0, 0.0, 1.0),
    }
}

fn matched() -> LinearFilterModel<2, 1> {
    let t = truth();
    LinearFilterModel {
        f: t.f,
        h: t.h,
        q: t.q,
        r: t.r,
        x0: t.m0,
        p0: t.p0,
    }
}

/// Q 5× too small, R 3× too large, start 4 m off with a P0 that does not cover it well.
fn mismatched() -> LinearFilterModel<2, 1> {
    let t = truth();
    LinearFilterModel {
        q: t.q * 0.2,
        r: t.r * 3.0,
        x0: t.m0 + Vector2::new(4.0, 0.0),
        p0: Matrix2::new(9.0, 0.0, 0.0, 0.5),
        ..matched()
    }
}

#[test]
fn matched_lincov_equals_the_kalman_covariance() {
    let mut lc = LinearLinCov::new(truth(), matched());
    for _ in 0..EPOCHS {
        let e = lc.step().unwrap();
        let scale = e.p_filter.norm();
        assert!(
            (e.p_true - e.p_filter).norm() <= 1e-9 * scale,
            "k {}: {} vs {}",
            e.k,
            e.p_true,
            e.p_filter
        );
        assert!(e.mean_error.norm() < 1e-12);
        assert!((e.nees_ratio - 1.0).abs() < 1e-9);
    }
}

/// Per epoch: the Monte Carlo mean of e eᵀ (diagonal), its standard error, and the mean NEES/N.
fn monte_carlo(
    filter: &LinearFilterModel<2, 1>,
    runs: usize,
) -> Vec<([f64; 2], [f64; 2], f64, f64)> {
    let t = truth();
    let mut rng = ChaCha8Rng::seed_from_u64(2026);
    let chol_q = t.q.cholesky().unwrap().l();
    let chol_p0 = t.p0.cholesky().unwrap().l();
    let sigma_r = t.r[(0, 0)].sqrt();
    let mut n = || -> f64 { StandardNormal.sample(&mut rng) };
    // Per epoch: Σ e_i², Σ e_i⁴, Σ NEES, Σ NEES².
    let mut sums = vec![([0.0; 2], [0.0; 2], 0.0, 0.0); EPOCHS];
    for _ in 0..runs {
        let mut x = t.m0 + chol_p0 * Vector2::new(n(), n());
        let mut ekf = Ekf::new(filter.x0, filter.p0).unwrap();
        for s in sums.iter_mut() {
            x = t.f * x + chol_q * Vector2::new(n(), n());
            let z = (t.h * x)[(0, 0)] + sigma_r * n();
            let x_next = filter.f * ekf.x;
            ekf.predict(x_next, &filter.f, &filter.q).unwrap();
            let h_row = filter.h.transpose();
            let h0 = (filter.h * ekf.x)[(0, 0)];
            let prior = ekf.x;
            ekf.update_linearized(&prior, &[(h0, h_row, z, filter.r[(0, 0)])])
                .unwrap();
            let e = ekf.x - x;
            for i in 0..2 {
                s.0[i] += e[i] * e[i];
                s.1[i] += e[i].powi(4);
            }
            let nees = (e.transpose() * ekf.p.try_inverse().unwrap() * e)[(0, 0)] / 2.0;
            s.2 += nees;
            s.3 += nees * nees;
        }
    }
    let m = runs as f64;
    sums.into_iter()
        .map(|(e2, e4, nees, nees2)| {
            let mean = [e2[0] / m, e2[1] / m];
            let se = [0, 1].map(|i| ((e4[i] / m - mean[i] * mean[i]) / m).sqrt());
            let nees_mean = nees / m;
            let nees_se = ((nees2 / m - nees_mean * nees_mean) / m).sqrt();
            (mean, se, nees_mean, nees_se)
        })
        .collect()
}

#[test]
fn mismatched_lincov_matches_a_20000_run_monte_carlo_of_the_filter() {
    let filter = mismatched();
    let mc = monte_carlo(&filter, 20_000);
    let mut lc = LinearLinCov::new(truth(), filter);
    let mut far_from_own_p = false;
    for (k, (mean, se, nees, nees_se)) in mc.iter().enumerate() {
        let e = lc.step().unwrap();
        assert_eq!(e.k, k + 1);
        for i in 0..2 {
            let predicted = e.p_true[(i, i)];
            // 4 standard errors: a 6e-5 two-sided chance per comparison for a correct LinCov.
            assert!(
                (predicted - mean[i]).abs() <= 4.0 * se[i],
                "epoch {}, state {i}: LinCov {predicted:.5} vs Monte Carlo {:.5} ± {:.5}",
                k + 1,
                mean[i],
                se[i]
            );
            if (predicted / e.p_filter[(i, i)] - 1.0).abs() > 0.3 {
                far_from_own_p = true;
            }
        }
        assert!(
            (e.nees_ratio - nees).abs() <= 4.0 * nees_se,
            "epoch {}: NEES ratio {} vs Monte Carlo {nees} ± {nees_se}",
            k + 1,
            e.nees_ratio
        );
    }
    // The mismatch matters: the filter's own P is more than 30 % off somewhere, so agreeing with
    // the Monte Carlo is not agreeing with P.
    assert!(far_from_own_p);
}
