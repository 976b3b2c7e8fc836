//! The statistics of Monte Carlo figures (`trade compare`, `trade --method both`, the check of a
//! design): standard errors of what a trade summary holds (RMSE over N runs, ANEES, bad-run
//! fractions) and the confidence interval of a difference B − A.
//!
//! A trade summary keeps no per-run errors, only each RMSE, the mean final error per state and
//! the number of runs N, so the standard errors come from large-sample formulas under Gaussian
//! errors:
//!
//! * a mean square over N runs of an error with mean μ and variance σ² has
//!   Var = (2σ⁴ + 4μ²σ²) / N, and by the delta method SE(RMSE) = SE(MSE) / (2 RMSE); with μ = 0
//!   this is the χ² result SE(RMSE) = RMSE / √(2N);
//! * for any Gaussian error (any mean, any covariance of a vector norm such as `pos_m`),
//!   2σ⁴ + 4μ²σ² ≤ 2 MSE², so RMSE / √(2N) is an upper bound; it is used where the mean is not
//!   in the summary (`pos_m`, `vel_mps`) and for time averages (the standard deviation of an
//!   average of correlated estimates is at most the average of their standard deviations);
//! * a filter whose NEES is c·χ²(dof) per run has SE(ANEES) ≤ ANEES · √(2 / (dof · N)) by the
//!   same argument.
//!
//! Heavy-tailed errors (diverged runs) make these intervals too narrow.

use serde::Serialize;

/// Two-sided 95 % normal quantile.
pub const Z95: f64 = 1.959_963_984_540_054;

/// Standard error of an RMSE over `n` runs whose mean error is unknown: the Gaussian upper bound
/// RMSE / √(2N).
pub fn se_rmse_bound(rmse: f64, n: u64) -> f64 {
    rmse / (2.0 * n.max(1) as f64).sqrt()
}

/// Standard error of an RMSE over `n` runs of a Gaussian error whose mean over the runs is
/// `mean`: √((2σ⁴ + 4μ²σ²)/N) / (2 RMSE) with σ² = RMSE² − μ².
pub fn se_rmse_with_mean(rmse: f64, mean: f64, n: u64) -> f64 {
    if rmse <= 0.0 {
        return 0.0;
    }
    let var = (rmse * rmse - mean * mean).max(0.0);
    let se_mse = ((2.0 * var * var + 4.0 * mean * mean * var) / n.max(1) as f64).sqrt();
    se_mse / (2.0 * rmse)
}

/// Standard error of an ANEES over `n` runs with `dof` degrees of freedom (scaled χ² NEES).
pub fn se_anees(anees: f64, dof: f64, n: u64) -> f64 {
    anees * (2.0 / (dof.max(1.0) * n.max(1) as f64)).sqrt()
}

/// Standard error of a fraction `p` of `n` runs (binomial).
pub fn se_fraction(p: f64, n: u64) -> f64 {
    (p * (1.0 - p) / n.max(1) as f64).sqrt()
}

/// One value of summary A or B and its standard error.
#[derive(Debug, Clone, Copy, Serialize)]
pub struct Estimate {
    /// The value in the summary.
    pub value: f64,
    /// Its Monte Carlo standard error.
    pub se: f64,
}

/// The difference B − A of two estimates from independent runs, with its 95 % interval.
#[derive(Debug, Clone, Copy, Serialize, PartialEq)]
pub struct Difference {
    /// B − A.
    pub diff: f64,
    /// (B − A) / A; `None` when A is 0.
    pub rel: Option<f64>,
    /// Standard error of the difference, √(SE_A² + SE_B²).
    pub se: f64,
    /// Lower end of the 95 % interval.
    pub ci_low: f64,
    /// Upper end of the 95 % interval.
    pub ci_high: f64,
    /// Whether the interval excludes 0.
    pub significant: bool,
}

impl Difference {
    /// B − A, treating the two estimates as independent (conservative for the same runs: their
    /// positive correlation would narrow the interval).
    pub fn of(a: Estimate, b: Estimate) -> Difference {
        Difference::with_se(a.value, b.value, a.se.hypot(b.se))
    }

    /// B − A with the standard error `se` of the difference (e.g. from paired runs).
    pub fn with_se(a: f64, b: f64, se: f64) -> Difference {
        let diff = b - a;
        let half = Z95 * se;
        Difference {
            diff,
            rel: (a != 0.0).then(|| diff / a),
            se,
            ci_low: diff - half,
            ci_high: diff + half,
            significant: diff.abs() > half,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn zero_mean_rmse_error_is_the_chi_square_result() {
        let (rmse, n) = (3.0, 50);
        let bound = se_rmse_bound(rmse, n);
        assert!((bound - 3.0 / 10.0).abs() < 1e-12);
        assert!((se_rmse_with_mean(rmse, 0.0, n) - bound).abs() < 1e-12);
    }

    #[test]
    fn the_bound_holds_for_any_mean() {
        for mean in [0.0, 0.5, 1.0, 2.0, 2.9, 3.0] {
            assert!(se_rmse_with_mean(3.0, mean, 40) <= se_rmse_bound(3.0, 40) + 1e-15);
        }
        // A pure bias has no sampling spread.
        assert_eq!(se_rmse_with_mean(3.0, 3.0, 40), 0.0);
    }

    #[test]
    fn the_rmse_error_matches_a_simulation() {
        // RMSE over N = 100 standard-normal draws, repeated 2000 times: its spread is
        // 1/√200 ≈ 0.0707.
        use rand::{RngExt, SeedableRng};
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(7);
        let normal = |rng: &mut rand_chacha::ChaCha8Rng| {
            let (u, v): (f64, f64) = (rng.random(), rng.random());
            (-2.0 * (1.0 - u).ln()).sqrt() * (std::f64::consts::TAU * v).cos()
        };
        let rmses: Vec<f64> = (0..2000)
            .map(|_| {
                let ms = (0..100).map(|_| normal(&mut rng).powi(2)).sum::<f64>() / 100.0;
                ms.sqrt()
            })
            .collect();
        let m = rmses.iter().sum::<f64>() / rmses.len() as f64;
        let sd = (rmses.iter().map(|r| (r - m).powi(2)).sum::<f64>() / 1999.0).sqrt();
        let predicted = se_rmse_bound(1.0, 100);
        assert!(
            (sd / predicted - 1.0).abs() < 0.08,
            "sd {sd} vs {predicted}"
        );
    }

    #[test]
    fn identical_estimates_differ_by_nothing() {
        let a = Estimate {
            value: 2.0,
            se: 0.1,
        };
        let d = Difference::of(a, a);
        assert_eq!(d.diff, 0.0);
        assert!(!d.significant);
        assert!(d.ci_low < 0.0 && d.ci_high > 0.0);
    }

    #[test]
    fn a_difference_of_many_standard_errors_is_significant() {
        let a = Estimate {
            value: 2.0,
            se: 0.1,
        };
        let b = Estimate {
            value: 2.5,
            se: 0.1,
        };
        let d = Difference::of(a, b);
        assert!(d.significant);
        assert!((d.se - 0.1 * 2f64.sqrt()).abs() < 1e-12);
        assert_eq!(d.rel, Some(0.25));
        let c = Estimate {
            value: 2.2,
            se: 0.1,
        };
        assert!(!Difference::of(a, c).significant);
    }
}
