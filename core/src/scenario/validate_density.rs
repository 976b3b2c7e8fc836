//! Range checks for the density-adaptation settings (`[filter.density]`,
//! `[filter.density.training]`, seed 001 §IV–V); every error names field, value and range.

use super::config::*;
use super::error::ScenarioError;
use super::validate_range::R;
use super::validate_range::{Checker, Range, named};

/// Counts from `lo` to `hi`, both included.
fn count(lo: usize, hi: usize) -> Range {
    Range::ge(lo as f64).le(hi as f64)
}

/// Fractions and probabilities: `> 0` (or `>= 0`) and `< 1`.
fn open_fraction() -> Range {
    Range::gt(0.0).lt(1.0)
}

fn fraction_or_zero() -> Range {
    Range::ge(0.0).lt(1.0)
}

impl DensityFilterConfig {
    /// Check ranges of the density-adaptation settings; errors name `prefix.field`.
    pub fn validate(&self, prefix: &str) -> R {
        self.check(prefix, &mut Checker::new())
    }

    pub(super) fn check(&self, prefix: &str, c: &mut Checker) -> R {
        let f = |name: &str| format!("{prefix}.{name}");
        c.range(f("cm_batch"), self.cm_batch, count(2, 10_000))?;
        c.range(f("ac_p0"), self.ac_p0, open_fraction())?;
        c.range(f("ac_q"), self.ac_q, fraction_or_zero())?;
        if let Some(k) = self.ac_initial {
            c.range(f("ac_initial"), k, Range::gt(0.0).lt(100.0))?;
        }
        if let Some(climatology) = &self.climatology {
            climatology.validate(&f("climatology"))?;
        }
        if self.network.trim().is_empty() {
            return Err(ScenarioError::invalid(
                f("network"),
                "must name a network file",
            ));
        }
        let tau = Range::gt(0.0).lt(1e6).unit("s");
        c.range(f("consider_tau_s"), self.consider_tau_s, tau)?;
        c.range(f("consider_pss"), self.consider_pss, fraction_or_zero())?;
        c.range(f("consider_p0"), self.consider_p0, open_fraction())?;
        c.range(f("adam_beta1"), self.adam_beta1, fraction_or_zero())?;
        c.range(f("adam_beta2"), self.adam_beta2, fraction_or_zero())?;
        c.range(f("adam_epsilon"), self.adam_epsilon, open_fraction())?;
        let step = Range::ge(0.0).lt(10.0);
        c.range(f("adam_step"), self.adam_step, step)?;
        c.range(f("patience"), self.patience, count(1, 1_000))?;
        let threshold = Range::ge(0.0);
        c.range(f("loss_threshold"), self.loss_threshold, threshold)?;
        c.range(f("max_iterations"), self.max_iterations, count(1, 100_000))?;
        c.range(f("window"), self.window, count(1, 1_000))?;
        if let Some(w) = self.slope_window {
            c.range(f("slope_window"), w, count(1, 1_000))?;
        }
        let slope = Range::gt(0.0).le(100.0).unit("1/km");
        c.range(f("slope_sigma_per_km"), self.slope_sigma_per_km, slope)?;
        c.range(
            f("slope_log_density_sigma"),
            self.slope_log_density_sigma,
            open_fraction(),
        )?;
        if let Some(n) = self.consider_match_epochs {
            c.range(f("consider_match_epochs"), n, count(1, 1_000))?;
            if self.slope_window.is_none() {
                return Err(ScenarioError::invalid(
                    f("consider_match_epochs"),
                    "needs filter.density.slope_window: the prediction error it matches is the level-and-slope correction's",
                ));
            }
        }
        self.training.check(&f("training"), c)
    }
}

impl DensityTrainingConfig {
    /// Check ranges of the training settings; errors name `prefix.field`.
    pub fn validate(&self, prefix: &str) -> R {
        self.check(prefix, &mut Checker::new())
    }

    pub(super) fn check(&self, prefix: &str, c: &mut Checker) -> R {
        let f = |name: &str| format!("{prefix}.{name}");
        c.range(f("trajectories"), self.trajectories, count(1, 1_000_000))?;
        c.range(f("hidden"), self.hidden, count(1, 10_000))?;
        c.range(f("epochs"), self.epochs, count(1, 1_000_000))?;
        c.range(f("batch_size"), self.batch_size, count(1, 100_000_000))?;
        let duration = Range::gt(0.0).le(7200.0).unit("s");
        c.range(f("duration_s"), self.duration_s, duration)?;
        let interval = Range::gt(0.0)
            .lt(named("duration_s", self.duration_s))
            .unit("s");
        c.range(f("sample_interval_s"), self.sample_interval_s, interval)?;
        c.range(f("lr_max"), self.lr_max, Range::gt(0.0).lt(10.0))?;
        let lr_min = Range::gt(0.0).le(named("lr_max", self.lr_max));
        c.range(f("lr_min"), self.lr_min, lr_min)?;
        c.range(
            f("validation_fraction"),
            self.validation_fraction,
            open_fraction(),
        )?;
        let [lo, hi] = self.fit_altitude_km;
        let bottom = Range::ge(-100.0).lt(1000.0).unit("km");
        c.range(f("fit_altitude_km[0]"), lo, bottom)?;
        let top = Range::gt(named("fit_altitude_km[0]", lo))
            .le(1000.0)
            .unit("km");
        c.range(f("fit_altitude_km[1]"), hi, top)?;
        self.check_bands(prefix)
    }

    /// `bands_km`: empty (one network) or at least three increasing edges.
    fn check_bands(&self, prefix: &str) -> R {
        if self.bands_km.is_empty() {
            return Ok(());
        }
        let field = |name: &str| format!("{prefix}.{name}");
        if self.bands_km.len() < 3 {
            return Err(ScenarioError::invalid(
                field("bands_km"),
                "needs at least 3 edges (2 bands), e.g. [0, 40, 70, 130]; leave it empty for one network",
            ));
        }
        for (k, w) in self.bands_km.windows(2).enumerate() {
            if !(w[0].is_finite() && w[1].is_finite() && w[1] > w[0]) {
                return Err(ScenarioError::invalid(
                    field(&format!("bands_km[{}]", k + 1)),
                    format!("edges must increase ({} km then {} km)", w[0], w[1]),
                ));
            }
        }
        Ok(())
    }
}
