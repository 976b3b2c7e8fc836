//! What entrynav's studies look like: SVG figures and self-contained HTML reports, rendered to
//! strings from the study layer's results (`entrynav-studies`) — no file is written here; the
//! front ends (the `entrynav` command, the Python package) write what they get.
//!
//! * [`chart`] — line, categorical and scatter charts with readable ticks, labels and legends
//!   (plotters' SVG backend: no fonts or system libraries);
//! * [`trade_figures`], [`delivery_figures`], [`grid_figures`], [`observe_figure`] — the figures
//!   of a trade, of guided delivery, of a grid, of an observability analysis;
//! * [`density_figure`] — seed 001 Fig. 10, the density error of a density estimator;
//! * [`report`] — the HTML pages of a trade and of a grid.

pub mod chart;
mod consistency_figures;
pub mod delivery_figures;
pub mod density_figure;
pub mod error;
pub mod figure;
mod figure_parts;
pub mod grid_figures;
pub mod observe_figure;
pub mod report;
pub mod trade_figures;

pub use error::{RenderError, Result};
