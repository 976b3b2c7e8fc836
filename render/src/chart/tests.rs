//! Readability of every figure, checked on the SVG text: at least two tick labels per axis,
//! no float noise in a label, units in the axis labels, the legend right of the data area,
//! beacon names on the fusion weights.

use super::categorical::{Series, category_chart};
use super::labels::WeightNames;
use super::legend;
use super::svg_text::{SvgText, has_float_noise, is_number, texts, width};
use super::{Curve, Frame, line_chart};
use entrynav::estimation::nav::FilterKind;
use entrynav::sim::{McOptions, TradeReport, run_trade};
use entrynav_loader as load;

/// The checks every figure must pass; returns its legend texts.
fn check_readable(name: &str, svg: &str, numeric_x: bool) -> Vec<String> {
    let t = texts(svg);
    let y_ticks: Vec<&SvgText> = t.iter().filter(|s| s.anchor == "end").collect();
    let x_ticks: Vec<&SvgText> = t
        .iter()
        .filter(|s| s.anchor == "middle" && !s.rotated && (!numeric_x || is_number(&s.text)))
        .filter(|s| s.y < t.iter().map(|v| v.y).fold(0.0, f64::max) - 1.0) // not the x label
        .filter(|s| s.y > 40.0) // not the caption
        .collect();
    assert!(y_ticks.len() >= 2, "{name}: y ticks {y_ticks:?}");
    assert!(x_ticks.len() >= 2, "{name}: x ticks {x_ticks:?}");
    for s in y_ticks.iter().chain(&x_ticks) {
        assert!(!has_float_noise(&s.text), "{name}: noisy label {}", s.text);
    }
    assert!(
        y_ticks.iter().all(|s| is_number(&s.text)),
        "{name}: {y_ticks:?}"
    );
    let y_label = t.iter().find(|s| s.rotated).expect("a y axis label");
    let x_label = t
        .iter()
        .filter(|s| s.anchor == "middle" && !s.rotated)
        .max_by(|a, b| a.y.total_cmp(&b.y))
        .expect("an x axis label");
    for l in [y_label, x_label] {
        let unit = l.text.rsplit_once('(').map(|(_, u)| u);
        assert!(
            unit.is_some_and(|u| u.ends_with(')') && u.len() > 1),
            "{name}: axis label without a unit: {}",
            l.text
        );
        assert!(!l.text.contains('_'), "{name}: code name in {}", l.text);
    }
    let legend_texts: Vec<&SvgText> = t.iter().filter(|s| s.anchor == "start").collect();
    assert!(!legend_texts.is_empty(), "{name}: no legend");
    let names: Vec<&str> = legend_texts.iter().map(|s| s.text.as_str()).collect();
    let data_right = width(svg) - legend::width(&names) as f64;
    for s in y_ticks.iter().chain(&x_ticks) {
        assert!(
            s.x <= data_right,
            "{name}: tick {} at {} in the legend",
            s.text,
            s.x
        );
    }
    for s in &legend_texts {
        assert!(
            s.x > data_right,
            "{name}: legend {} at {} inside the data",
            s.text,
            s.x
        );
    }
    names.iter().map(|s| s.to_string()).collect()
}

fn frame<'a>(log_y: bool) -> Frame<'a> {
    Frame {
        title: "t",
        x_label: "time (s)",
        y_label: "longitude error RMSE (rad)",
        log_y,
        size: (900, 480),
    }
}

#[test]
fn a_log_axis_within_one_decade_gets_tick_labels() {
    let points: Vec<(f64, f64)> = (1..300)
        .map(|k| (k as f64, 1.2e-5 + 2.0e-5 * (k as f64 / 300.0)))
        .collect();
    let curves = [Curve {
        name: "ekf".into(),
        points,
        dashed: false,
        color: None,
    }];
    let svg = line_chart(&frame(true), &curves).unwrap().unwrap();
    assert_eq!(check_readable("narrow log", &svg, true), ["ekf"]);
}

#[test]
fn noisy_and_tiny_values_get_clean_labels() {
    let points: Vec<(f64, f64)> = (0..50)
        .map(|k| {
            (
                0.1 * k as f64,
                3.0000000000000004e-5 * (1.0 + 0.1 * k as f64),
            )
        })
        .collect();
    let curves = [
        Curve {
            name: "mean error".into(),
            points: points.clone(),
            dashed: false,
            color: None,
        },
        Curve {
            name: "+3σ".into(),
            points: points.iter().map(|(x, y)| (*x, -y)).collect(),
            dashed: true,
            color: None,
        },
    ];
    let svg = line_chart(&frame(false), &curves).unwrap().unwrap();
    check_readable("noisy linear", &svg, true);
    assert!(svg.contains("e-6"), "engineering exponent expected");
}

#[test]
fn categorical_axes_label_every_cell() {
    let cells: Vec<String> = ["c0", "c1", "c2"].map(String::from).to_vec();
    let series = [
        Series {
            name: "ekf".into(),
            values: vec![Some(10.0), Some(12.0), None],
        },
        Series {
            name: "dcifaif".into(),
            values: vec![Some(8.0), Some(9.5), Some(11.0)],
        },
    ];
    let f = Frame {
        x_label: "grid cell (see the table)",
        y_label: "final position error RMSE (m)",
        ..frame(true)
    };
    let svg = category_chart(&f, &cells, &series).unwrap().unwrap();
    check_readable("categorical", &svg, false);
    let t = texts(&svg);
    for c in &cells {
        assert!(t.iter().any(|s| &s.text == c), "cell {c} not labelled");
    }
    // Markers, not a line joining the cells.
    assert!(!svg.contains("<polyline fill=\"none\" opacity=\"1\" stroke=\"#1F77B4\""));
    assert_eq!(
        svg.matches("<circle").count(),
        5 + 2,
        "5 values and 2 legend dots"
    );
}

fn small_trade() -> (TradeReport, WeightNames) {
    let (cfg, dir) = load::resolve("four-beacon-fusion", load::Base::CurrentDir)
        .unwrap()
        .into_parts();
    let scenario = load::build(cfg, &dir).unwrap();
    let filters = FilterKind::parse_list("ekf,dcifaif", &scenario.onboard).unwrap();
    let report = run_trade(&scenario, &filters, &McOptions::new(3, 1), &|_| {}).unwrap();
    (report, WeightNames::of_scenario(&scenario))
}

#[test]
fn every_trade_figure_is_readable_and_weights_name_the_beacons() {
    let (report, names) = small_trade();
    let figs = crate::trade_figures::trade_figures(&report, &names).unwrap();
    assert!(
        figs.len() > 2 * report.states.len(),
        "{} figures",
        figs.len()
    );
    for f in &figs {
        check_readable(&f.file, &f.svg, true);
    }
    let w = figs
        .iter()
        .find(|f| f.file.ends_with("dcifaif_weights.svg"))
        .expect("a weights figure");
    let legend = check_readable(&w.file, &w.svg, true);
    assert_eq!(legend, names.radio_beacons);
    assert_eq!(
        legend,
        ["surface-1", "surface-2", "orbiter-1", "orbiter-2"],
        "beacon names of four-beacon-fusion"
    );
    for filter in ["ekf", "dcifaif"] {
        let d = figs
            .iter()
            .find(|f| f.file.ends_with(&format!("{filter}_dispersion.svg")))
            .expect("a dispersion figure per filter");
        assert!(d.svg.contains("downrange error (m)") && d.svg.contains("crossrange error (m)"));
        // 3 runs' dots + 1 legend dot.
        assert_eq!(d.svg.matches("<circle").count(), 3 + 1, "{}", d.file);
    }
}
