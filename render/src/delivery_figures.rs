//! The delivery footprint of a study with `[guidance]` (issue 28): where every run deployed
//! relative to the target, per row, with the row's 99 % ellipse — as SVG figures for `--plots`
//! and as the report's "Delivery at deployment" section.

use crate::chart::Frame;
use crate::chart::scatter::{Cloud, ellipse, scatter_chart};
use crate::error::Result;
use crate::figure::{Figure, Kind};
use crate::report::html::{Cell, figures, note, table};
use entrynav::sim::guided::delivery::{DeliveryReport, DeliveryRow};

/// Most runs drawn per row (the ellipse and the statistics are over every run).
const MAX_DOTS: usize = 2000;

/// The deployment points of row `row` (downrange, crossrange miss \[m\]), first [`MAX_DOTS`].
fn points(d: &DeliveryReport, row: usize) -> Vec<(f64, f64)> {
    d.per_run
        .iter()
        .filter_map(|run| run.get(row)?.as_ref().ok())
        .map(|dl| (dl.downrange_m, dl.crossrange_m))
        .take(MAX_DOTS)
        .collect()
}

fn cloud(d: &DeliveryReport, row: usize) -> Cloud {
    let r = &d.rows[row];
    let outline = match (r.ellipse_99, r.mean_downrange_m, r.mean_crossrange_m) {
        (Some(e), Some(dr), Some(cr)) => ellipse(
            (dr, cr),
            e.semi_major_m,
            e.semi_minor_m,
            e.orientation_deg.to_radians(),
        ),
        _ => Vec::new(),
    };
    Cloud {
        name: r.name.clone(),
        points: points(d, row),
        outline,
    }
}

/// Two figures: the guided rows (perfect navigation and every filter in the loop) on one scale,
/// so the growth of the footprint with navigation error shows; and the unguided constant bank on
/// its own (tens of kilometres: it would hide the others).
pub fn delivery_figures(d: &DeliveryReport) -> Result<Vec<Figure>> {
    let sc = &d.scenario;
    let shown = if d.runs > MAX_DOTS {
        format!("first {MAX_DOTS} runs")
    } else {
        format!("{} runs", d.runs)
    };
    let guided: Vec<Cloud> = (0..d.rows.len())
        .filter(|&i| d.rows[i].name != "unguided")
        .map(|i| cloud(d, i))
        .collect();
    let unguided: Vec<Cloud> = (0..d.rows.len())
        .filter(|&i| d.rows[i].name == "unguided")
        .map(|i| cloud(d, i))
        .collect();
    let mut out = Vec::new();
    for (file, what, clouds) in [
        (
            "delivery_footprint",
            format!("{} guidance", d.algorithm),
            guided,
        ),
        (
            "delivery_unguided",
            "unguided constant bank".to_string(),
            unguided,
        ),
    ] {
        let title = format!("{what}: deployment miss, {shown}; 99 % ellipse dashed");
        let mut clouds = clouds;
        if clouds.is_empty() {
            continue;
        }
        clouds.push(Cloud {
            name: "target".to_string(),
            points: vec![(0.0, 0.0)],
            outline: Vec::new(),
        });
        let frame = Frame {
            title: &title,
            x_label: "downrange miss (m)",
            y_label: "crossrange miss (m)",
            log_y: false,
            size: (700, 560),
        };
        if let Some(svg) = scatter_chart(&frame, &clouds)? {
            out.push(Figure {
                file: format!("{sc}_{file}.svg"),
                kind: Kind::Delivery,
                svg,
            });
        }
    }
    Ok(out)
}

fn m(v: Option<f64>) -> Cell {
    Cell::num(v.map_or_else(|| "–".to_string(), |x| format!("{x:.1}")))
}

fn row_cells(r: &DeliveryRow) -> Vec<Cell> {
    vec![
        Cell::text(r.name.clone()),
        Cell::num(format!("{} / {}", r.deployed, r.failures)),
        m(r.mean_miss_m),
        m(r.rms_miss_m),
        m(r.median_miss_m),
        m(r.max_miss_m),
        m(r.mean_downrange_m),
        m(r.mean_crossrange_m),
        Cell::num(r.ellipse_99.map_or_else(
            || "–".to_string(),
            |e| {
                format!(
                    "{:.0} × {:.0} @ {:.1}°",
                    e.semi_major_m, e.semi_minor_m, e.orientation_deg
                )
            },
        )),
        m(r.max_bank_rate_deg_s),
        m(r.rms_nav_position_error_m),
    ]
}

/// The report section's content: what the rows are, the table, the footprints.
pub fn delivery_section(d: &DeliveryReport, figs: &[Figure]) -> String {
    let mut s = note(&format!(
        "The same {} runs (seed {}) flown by {} guidance in closed loop: perfect-nav feeds \
         guidance the truth (a reference, not a navigation system), each filter row its own \
         estimate and the sensed drag, unguided flies the constant reference bank. Misses are \
         surface distances from deployment to the target, downrange positive past the target, \
         crossrange positive with the target to the right; the 99 % ellipse is over the runs \
         that deployed (semi-axes in m, major axis from downrange); nav is the RMS position \
         error at deployment. Bank rate limit {:.1}°/s.",
        d.runs, d.seed, d.algorithm, d.bank_rate_limit_deg_s
    ));
    let rows: Vec<Vec<Cell>> = d.rows.iter().map(row_cells).collect();
    s += &table(
        &[
            "row",
            "deployed / failed",
            "mean miss (m)",
            "RMS miss (m)",
            "median (m)",
            "max (m)",
            "mean downrange (m)",
            "mean crossrange (m)",
            "99 % ellipse",
            "max bank rate (°/s)",
            "nav (m)",
        ],
        &rows,
    );
    s += &figures(
        figs.iter()
            .filter(|f| f.kind == Kind::Delivery)
            .map(|f| f.svg.as_str()),
    );
    s
}
