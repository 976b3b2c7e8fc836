//! A local level-and-slope correction of the network density, fitted to the densities the last
//! measurement epochs imply (USKF-NN, `filter.density.slope_window`).
//!
//! **Why.** Algorithm 2 (seed 001 eq. 52–60) adapts the network at one point, the prior
//! altitude, so it fits the density *level* there. The network's output is ϱ = √(−log₁₀ρ)
//! (eq. 29–31), and a shift δ of ϱ changes ln ρ by −2 ln10 · ϱ · δ: a large level change also
//! multiplies the local log-slope d ln ρ/dh by (ϱ + δ)/ϱ. On real polar Mars-GRAM sets the density
//! is 0.3–6 % of the onboard model's (heights are above a 17–22 km lower areoid), and after the
//! adaptation the network's local scale height is 4.3 km where the truth's is 6–8 km
//! (docs/density.md, "Polar Mars-GRAM sets"). Every prediction over a 0.25 s step then misses the
//! density by 1–2 %, and the update puts that into v, γ and r, which are only dead-reckoned.
//!
//! **What.** The onboard density becomes `ρ(h) = NN(h, ξ) · exp(a + b (h − h_k))` near the
//! vehicle: the exponential model of seed 001 eq. 16 applied as a correction, with its level
//! (a ↔ ρ₀) and its log-slope (b ↔ 1/h_s) — the two parameters of the augmentation approach of
//! seed 001 eq. 27 (refs. [10, 29] there) — estimated here not in the filter state but by
//! weighted least squares with a priori information (Tapley, Schutz & Born, *Statistical Orbit
//! Determination*, 2004, §4.3.3) over a window of epochs, the window extension
//! of seed 001 §VI applied to (a, b). Each epoch contributes one pseudo-measurement, the
//! log-density `u_j` that minimises the epoch's loss (eq. 52) at its prior state (a Gauss–Newton
//! solve, [`super::mlo::LossContext::measured_log_density`]), at the prior altitude `h_j`. The
//! residuals `d_j = u_j − ln NN(h_j, ξ)` are fitted by `d = a + b (h − h_k)` with weights
//! `1/σ_u²` and the prior `b ~ N(0, σ_b²)` (`slope_sigma_per_km`), so that the slope stays zero
//! when the window spans no altitude (a single epoch, a level flight).

use std::collections::VecDeque;

/// `exp(level + slope · (h − ref))`: the correction factor of the network density
/// (identity by default).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct LogLinearCorrection {
    /// a: ln of the factor at the reference altitude.
    pub level: f64,
    /// b: d ln(factor)/dh \[1/m\].
    pub slope_per_m: f64,
    /// h_k: reference altitude \[m\].
    pub ref_altitude_m: f64,
}

impl LogLinearCorrection {
    /// The factor at altitude `h_m`; exactly 1 for the identity.
    #[inline]
    pub fn factor(&self, h_m: f64) -> f64 {
        if self.level == 0.0 && self.slope_per_m == 0.0 {
            return 1.0;
        }
        (self.level + self.slope_per_m * (h_m - self.ref_altitude_m)).exp()
    }
}

/// The window of (altitude, log-density) pseudo-measurements and the least-squares fit of the
/// correction.
#[derive(Debug, Clone, PartialEq)]
pub struct LocalSlopeFit {
    window: usize,
    /// 1/σ_b² \[m²\].
    slope_prior_info: f64,
    /// σ_u² of one pseudo-measurement.
    log_density_var: f64,
    samples: VecDeque<(f64, f64)>,
}

impl LocalSlopeFit {
    /// A fit over the last `window` epochs with the slope prior σ_b = `slope_sigma_per_km`
    /// \[1/km\] and pseudo-measurement standard deviation `log_density_sigma` (in ln ρ).
    pub fn new(window: usize, slope_sigma_per_km: f64, log_density_sigma: f64) -> Self {
        let sb = slope_sigma_per_km * 1e-3;
        LocalSlopeFit {
            window: window.max(1),
            slope_prior_info: 1.0 / (sb * sb),
            log_density_var: log_density_sigma * log_density_sigma,
            samples: VecDeque::with_capacity(window.max(1) + 1),
        }
    }

    /// Add the pseudo-measurement `ln ρ = log_density` at altitude `altitude_m`, dropping the
    /// oldest beyond the window.
    pub fn push(&mut self, altitude_m: f64, log_density: f64) {
        self.samples.push_back((altitude_m, log_density));
        while self.samples.len() > self.window {
            self.samples.pop_front();
        }
    }

    /// Pseudo-measurements held.
    pub fn len(&self) -> usize {
        self.samples.len()
    }

    /// Whether none is held.
    pub fn is_empty(&self) -> bool {
        self.samples.is_empty()
    }

    /// The correction about `ref_altitude_m` that fits the window's residuals against the
    /// network log-density `ln_nn` (identity when the window is empty): the normal equations
    /// of `d_j = a + b x_j`, `x_j = h_j − h_k`, with the a priori information on b.
    pub fn fit(&self, ln_nn: impl Fn(f64) -> f64, ref_altitude_m: f64) -> LogLinearCorrection {
        if self.samples.is_empty() {
            return LogLinearCorrection::default();
        }
        let w = 1.0 / self.log_density_var;
        let (mut s0, mut s1, mut s2, mut t0, mut t1) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for &(h, u) in &self.samples {
            let (x, d) = (h - ref_altitude_m, u - ln_nn(h));
            s0 += w;
            s1 += w * x;
            s2 += w * x * x;
            t0 += w * d;
            t1 += w * d * x;
        }
        s2 += self.slope_prior_info;
        let det = s0 * s2 - s1 * s1;
        let (level, slope) = ((s2 * t0 - s1 * t1) / det, (s0 * t1 - s1 * t0) / det);
        if !(level.is_finite() && slope.is_finite()) {
            return LogLinearCorrection::default();
        }
        LogLinearCorrection {
            level,
            slope_per_m: slope,
            ref_altitude_m,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn recovers_level_and_slope_of_an_exponential_mismatch() {
        // Truth ln ρ = network + 0.3 − 2e-5·(h − 50 km): the fit about 50 km returns them.
        let mut f = LocalSlopeFit::new(8, 1.0, 0.003);
        let ln_nn = |h: f64| -h / 8.6e3;
        for k in 0..8 {
            let h = 52e3 - 250.0 * k as f64;
            f.push(h, ln_nn(h) + 0.3 - 2e-5 * (h - 50e3));
        }
        let c = f.fit(ln_nn, 50e3);
        assert!((c.level - 0.3).abs() < 1e-6, "{c:?}");
        assert!((c.slope_per_m + 2e-5).abs() < 1e-8, "{c:?}");
        // The slope prior (σ_b = 1/km) pulls b towards 0 by a part in 1e6 of the data's weight.
        assert!((c.factor(51e3) / (0.3 - 2e-5 * 1e3_f64).exp() - 1.0).abs() < 1e-5);
    }

    #[test]
    fn one_epoch_or_a_level_flight_gives_a_level_only() {
        let mut f = LocalSlopeFit::new(4, 0.1, 0.003);
        f.push(60e3, -1.0);
        let c = f.fit(|_| 0.0, 60e3);
        assert_eq!((c.level, c.slope_per_m), (-1.0, 0.0));
        for _ in 0..3 {
            f.push(60e3, -1.0);
        }
        let c = f.fit(|_| 0.0, 60e3);
        assert!(
            (c.level + 1.0).abs() < 1e-12 && c.slope_per_m == 0.0,
            "{c:?}"
        );
        assert_eq!(LogLinearCorrection::default().factor(1e5), 1.0);
        let empty = LocalSlopeFit::new(3, 0.1, 0.003);
        assert_eq!(empty.fit(|_| 0.0, 0.0), LogLinearCorrection::default());
    }
}
