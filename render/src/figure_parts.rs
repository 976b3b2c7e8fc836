//! Pieces every trade figure shares: sizes, a curve from a filter's time series, the time-axis
//! frame, and the list the figures are pushed into.

use crate::chart::{Curve, Frame};
use crate::figure::{Figure, Kind};
use entrynav::sim::FilterReport;

/// Size of a full-width figure (px).
pub const WIDE: (u32, u32) = (900, 480);
/// Size of one subplot of a grid of figures (px).
pub const SMALL: (u32, u32) = (560, 330);

pub(crate) fn series_points(
    f: &FilterReport,
    get: &dyn Fn(usize) -> Option<f64>,
) -> Vec<(f64, f64)> {
    f.series
        .times_s
        .iter()
        .enumerate()
        .filter_map(|(k, t)| get(k).map(|v| (*t, v)))
        .collect()
}

pub(crate) fn curve(name: impl Into<String>, points: Vec<(f64, f64)>, dashed: bool) -> Curve {
    Curve {
        name: name.into(),
        points,
        dashed,
        color: None,
    }
}

pub(crate) struct Out<'a> {
    pub(crate) sc: &'a str,
    pub(crate) figures: Vec<Figure>,
}

impl Out<'_> {
    pub(crate) fn push(&mut self, file: String, kind: Kind, svg: Option<String>) {
        if let Some(svg) = svg {
            self.figures.push(Figure {
                file: format!("{}_{file}.svg", self.sc),
                kind,
                svg,
            });
        }
    }
}

pub(crate) fn frame<'a>(
    title: &'a str,
    y_label: &'a str,
    log_y: bool,
    size: (u32, u32),
) -> Frame<'a> {
    Frame {
        title,
        x_label: "time (s)",
        y_label,
        log_y,
        size,
    }
}
