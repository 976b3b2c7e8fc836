//! One plotters coordinate for every axis of ours: linear or logarithmic, with the tick
//! positions of `ticks.rs` as its key points (plotters' own key points give a log axis within
//! one decade no labels at all).

use plotters::coord::ranged1d::{DefaultFormatting, KeyPointHint, Ranged};
use std::ops::Range;

/// An axis from `lo` to `hi` with fixed ticks.
#[derive(Debug, Clone)]
pub struct Axis {
    lo: f64,
    hi: f64,
    log: bool,
    ticks: Vec<f64>,
}

impl Axis {
    /// A linear axis over `lo..hi` with ticks at `ticks`.
    pub fn linear(lo: f64, hi: f64, ticks: &[f64]) -> Axis {
        Axis {
            lo,
            hi,
            log: false,
            ticks: ticks.to_vec(),
        }
    }

    /// A logarithmic axis over `lo..hi` (`0 < lo < hi`) with ticks at `ticks`.
    pub fn log(lo: f64, hi: f64, ticks: &[f64]) -> Axis {
        Axis {
            lo,
            hi,
            log: true,
            ticks: ticks.to_vec(),
        }
    }

    /// Position of `v` along the axis, 0 at `lo`, 1 at `hi`.
    fn fraction(&self, v: f64) -> f64 {
        if self.log {
            let v = v.max(self.lo * 1e-6);
            (v.ln() - self.lo.ln()) / (self.hi.ln() - self.lo.ln())
        } else {
            (v - self.lo) / (self.hi - self.lo)
        }
    }
}

impl Ranged for Axis {
    type FormatOption = DefaultFormatting;
    type ValueType = f64;

    fn map(&self, value: &f64, limit: (i32, i32)) -> i32 {
        let f = self.fraction(*value);
        let f = if f.is_finite() {
            f.clamp(-10.0, 11.0)
        } else {
            0.0
        };
        limit.0 + ((limit.1 - limit.0) as f64 * f).round() as i32
    }

    fn key_points<Hint: KeyPointHint>(&self, hint: Hint) -> Vec<f64> {
        // The ticks are the bold points; no light grid lines between them.
        if hint.weight().allow_light_points() {
            Vec::new()
        } else {
            self.ticks.clone()
        }
    }

    fn range(&self) -> Range<f64> {
        self.lo..self.hi
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn maps_linear_and_log_positions() {
        let a = Axis::linear(0.0, 10.0, &[0.0, 5.0, 10.0]);
        assert_eq!(a.map(&5.0, (0, 100)), 50);
        let l = Axis::log(1.0, 100.0, &[1.0, 10.0, 100.0]);
        assert_eq!(l.map(&10.0, (100, 0)), 50);
        assert_eq!(l.map(&100.0, (100, 0)), 0);
    }
}
