//! Seed 001 Fig. 10 (`entrynav train-density --evaluate … --plot`): the density error of the
//! onboard model at the true altitude over time, per run and as the RMS over all runs.

use crate::error::{RenderError, Result};
use entrynav::sim::density::density_eval::DensityEvalReport;

/// Seed 001 Fig. 10: percentage error of the filter's density model at the true altitude vs
/// time, one grey line per run (the first 50) and the RMS over all runs; values beyond 3× the
/// largest RMS after the first 10 s are drawn at the edge. SVG text.
pub fn density_error_figure(scenario: &str, r: &DensityEvalReport) -> Result<String> {
    let mut svg = String::new();
    draw_fig10(&mut svg, scenario, r)?;
    Ok(svg)
}

/// Fig. 10 of [`density_error_figure`] drawn into `svg`.
fn draw_fig10(svg: &mut String, scenario: &str, r: &DensityEvalReport) -> Result<()> {
    use plotters::prelude::*;
    let e = |e: DrawingAreaErrorKind<std::io::Error>| RenderError::Draw(e.to_string());
    let t1 = r.times_s.last().copied().unwrap_or(1.0);
    // y range: 3× the largest RMS after the first 10 s (the initial transient is clipped).
    let ymax = r
        .times_s
        .iter()
        .zip(&r.rms_profile_pct)
        .filter(|(t, v)| **t > 10.0 && v.is_finite())
        .fold(0.0_f64, |a, (_, v)| a.max(*v))
        .max(0.5)
        * 3.0;
    let clip = |v: f64| v.clamp(-ymax, ymax);
    let root = SVGBackend::with_string(svg, (960, 540)).into_drawing_area();
    root.fill(&WHITE).map_err(e)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!(
                "{scenario} {}: density error of the onboard model at the true altitude (RMSPE {:.3} %)",
                r.filter, r.rmspe_profile_pct
            ),
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..t1, -ymax..ymax)
        .map_err(e)?;
    chart
        .configure_mesh()
        .x_desc("time [s]")
        .y_desc("(rho_hat - rho)/rho [%]")
        .draw()
        .map_err(e)?;
    let grey = RGBColor(160, 160, 160);
    for run in &r.sample_runs_profile_pct {
        let pts: Vec<(f64, f64)> = r
            .times_s
            .iter()
            .copied()
            .zip(run.iter().copied().map(clip))
            .filter(|(_, y)| y.is_finite())
            .collect();
        chart
            .draw_series(LineSeries::new(pts, grey.stroke_width(1)))
            .map_err(e)?;
    }
    let red = RGBColor(214, 39, 40);
    for sign in [1.0, -1.0] {
        let pts: Vec<(f64, f64)> = r
            .times_s
            .iter()
            .copied()
            .zip(r.rms_profile_pct.iter().map(|v| clip(sign * v)))
            .filter(|(_, y)| y.is_finite())
            .collect();
        let s = chart
            .draw_series(LineSeries::new(pts, red.stroke_width(2)))
            .map_err(e)?;
        if sign > 0.0 {
            s.label("±RMS over all runs")
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], red));
        }
    }
    chart
        .configure_series_labels()
        .background_style(WHITE.mix(0.8))
        .border_style(BLACK)
        .draw()
        .map_err(e)?;
    root.present().map_err(e)?;
    Ok(())
}
