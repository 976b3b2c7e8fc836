//! Range checks for the density-adaptation settings (`[filter.density]`,
//! `[filter.density.training]`, seed 001 §IV–V); every error names field, value and range.

use super::config::*;
use super::error::ScenarioError;
use super::validate::{R, within};

impl DensityFilterConfig {
    /// Check ranges of the density-adaptation settings; errors name `prefix.field`.
    pub fn validate(&self, prefix: &str) -> R {
        let f = |name: &str| format!("{prefix}.{name}");
        let count = |name: &str, v: usize, lo: usize, hi: usize| -> R {
            if (lo..=hi).contains(&v) {
                Ok(())
            } else {
                Err(ScenarioError::range(
                    f(name),
                    v,
                    format!("must be between {lo} and {hi}"),
                ))
            }
        };
        count("cm_batch", self.cm_batch, 2, 10_000)?;
        within(&f("ac_p0"), self.ac_p0, 0.0, 1.0, "must be > 0 and < 1")?;
        within(
            &f("ac_q"),
            self.ac_q,
            -f64::MIN_POSITIVE,
            1.0,
            "must be >= 0 and < 1",
        )?;
        if let Some(k) = self.ac_initial {
            within(&f("ac_initial"), k, 0.0, 100.0, "must be > 0 and < 100")?;
        }
        if self.network.trim().is_empty() {
            return Err(ScenarioError::invalid(
                f("network"),
                "must name a network file",
            ));
        }
        within(
            &f("consider_tau_s"),
            self.consider_tau_s,
            0.0,
            1e6,
            "must be > 0 and < 1e6 s",
        )?;
        within(
            &f("consider_pss"),
            self.consider_pss,
            -f64::MIN_POSITIVE,
            1.0,
            "must be >= 0 and < 1",
        )?;
        within(
            &f("consider_p0"),
            self.consider_p0,
            0.0,
            1.0,
            "must be > 0 and < 1",
        )?;
        within(
            &f("adam_beta1"),
            self.adam_beta1,
            -f64::MIN_POSITIVE,
            1.0,
            "must be >= 0 and < 1",
        )?;
        within(
            &f("adam_beta2"),
            self.adam_beta2,
            -f64::MIN_POSITIVE,
            1.0,
            "must be >= 0 and < 1",
        )?;
        within(
            &f("adam_epsilon"),
            self.adam_epsilon,
            0.0,
            1.0,
            "must be > 0 and < 1",
        )?;
        within(
            &f("adam_step"),
            self.adam_step,
            -f64::MIN_POSITIVE,
            10.0,
            "must be >= 0 and < 10",
        )?;
        count("patience", self.patience, 1, 1_000)?;
        within(
            &f("loss_threshold"),
            self.loss_threshold,
            -f64::MIN_POSITIVE,
            1e12,
            "must be >= 0",
        )?;
        count("max_iterations", self.max_iterations, 1, 100_000)?;
        count("window", self.window, 1, 1_000)?;
        self.training.validate(&f("training"))
    }
}

impl DensityTrainingConfig {
    /// Check ranges of the training settings; errors name `prefix.field`.
    pub fn validate(&self, prefix: &str) -> R {
        let f = |name: &str| format!("{prefix}.{name}");
        let count = |name: &str, v: usize, lo: usize, hi: usize| -> R {
            if (lo..=hi).contains(&v) {
                Ok(())
            } else {
                Err(ScenarioError::range(
                    f(name),
                    v,
                    format!("must be between {lo} and {hi}"),
                ))
            }
        };
        count("trajectories", self.trajectories, 1, 1_000_000)?;
        count("hidden", self.hidden, 1, 10_000)?;
        count("epochs", self.epochs, 1, 1_000_000)?;
        count("batch_size", self.batch_size, 1, 100_000_000)?;
        within(
            &f("duration_s"),
            self.duration_s,
            0.0,
            7200.0,
            "must be > 0 and <= 7200 s",
        )?;
        within(
            &f("sample_interval_s"),
            self.sample_interval_s,
            0.0,
            self.duration_s,
            "must be > 0 and below duration_s",
        )?;
        within(&f("lr_max"), self.lr_max, 0.0, 10.0, "must be > 0 and < 10")?;
        within(
            &f("lr_min"),
            self.lr_min,
            0.0,
            self.lr_max * (1.0 + 1e-12),
            "must be > 0 and <= lr_max",
        )?;
        within(
            &f("validation_fraction"),
            self.validation_fraction,
            0.0,
            1.0,
            "must be > 0 and < 1",
        )?;
        let [lo, hi] = self.fit_altitude_km;
        within(
            &f("fit_altitude_km[0]"),
            lo,
            -100.001,
            1000.0,
            "must be >= -100 and < 1000 km",
        )?;
        if !(hi.is_finite() && hi > lo && hi <= 1000.0) {
            return Err(ScenarioError::range(
                f("fit_altitude_km[1]"),
                hi,
                format!("must be above fit_altitude_km[0] = {lo} and <= 1000 km"),
            ));
        }
        if !self.bands_km.is_empty() {
            if self.bands_km.len() < 3 {
                return Err(ScenarioError::invalid(
                    f("bands_km"),
                    "needs at least 3 edges (2 bands), e.g. [0, 40, 70, 130]; leave it empty for one network",
                ));
            }
            for (k, w) in self.bands_km.windows(2).enumerate() {
                if !(w[0].is_finite() && w[1].is_finite() && w[1] > w[0]) {
                    return Err(ScenarioError::invalid(
                        f(&format!("bands_km[{}]", k + 1)),
                        format!("edges must increase ({} km then {} km)", w[0], w[1]),
                    ));
                }
            }
        }
        Ok(())
    }
}
