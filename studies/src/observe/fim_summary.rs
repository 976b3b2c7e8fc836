//! The summary of a range Fisher information series that `entrynav observe --fim` prints before
//! its table: beacons in view, the epochs where F is singular, the extremes of det F and of the
//! bound tr F⁻¹ with their times, the time-averaged geometry index I (seed 002 eq. 54).

use entrynav::observability::FimEpoch;

/// A value and the time \[s\] it is reached.
pub type AtTime = (f64, f64);

/// The summary of a FIM series.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct FimSummary {
    /// Number of epochs.
    pub epochs: usize,
    /// First and last epoch times \[s\].
    pub span_s: (f64, f64),
    /// Fewest and most beacons in view.
    pub in_view: (usize, usize),
    /// Epochs where F is singular (the ranges alone do not determine the position).
    pub singular: usize,
    /// Smallest and largest det F.
    pub det: (Option<AtTime>, Option<AtTime>),
    /// Best (smallest) and worst (largest) tr F⁻¹, the bound on tr P.
    pub trace_inverse: (Option<AtTime>, Option<AtTime>),
    /// Time-averaged geometry index I.
    pub mean_index: f64,
}

impl FimSummary {
    /// The summary of `fim`; `None` without epochs.
    pub fn of(fim: &[FimEpoch]) -> Option<FimSummary> {
        let (first, last) = (fim.first()?, fim.last()?);
        let by = |key: fn(&FimEpoch) -> Option<f64>, max: bool| {
            fim.iter()
                .filter_map(|e| key(e).filter(|v| v.is_finite()).map(|v| (v, e.t)))
                .reduce(|a, b| if (b.0 > a.0) == max { b } else { a })
        };
        let det = |e: &FimEpoch| Some(e.summary.det);
        let inverse = |e: &FimEpoch| e.summary.trace_inverse;
        Some(FimSummary {
            epochs: fim.len(),
            span_s: (first.t, last.t),
            in_view: (
                fim.iter().map(|e| e.summary.count).min().unwrap_or(0),
                fim.iter().map(|e| e.summary.count).max().unwrap_or(0),
            ),
            singular: fim
                .iter()
                .filter(|e| e.summary.trace_inverse.is_none())
                .count(),
            det: (by(det, false), by(det, true)),
            trace_inverse: (by(inverse, false), by(inverse, true)),
            mean_index: fim.iter().map(|e| e.geometry_index).sum::<f64>() / fim.len() as f64,
        })
    }
}
