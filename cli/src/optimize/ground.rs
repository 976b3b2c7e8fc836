//! `entrynav optimize ground`: the ground-site design (`entrynav_studies::design::ground`), then
//! every file asked for (each attempted, so a closed standard output never costs a file), the
//! tables, and exit code 1 when the check finds the optimum worse.

use super::args::GroundArgs;
use super::files::{json_text, load_input, write_text};
use super::progress_bars::with_bars;
use super::tables::{print_check, print_lincov, print_search, print_sites};
use anyhow::Result;
use entrynav::observability::{DegreeSeries, Method};
use entrynav_studies::design::ground::fmt_value;
use entrynav_studies::design::ground_result::{GroundDesign, delta_range};
use entrynav_studies::design::run_ground_design;
use std::path::Path;

/// Run the command.
pub fn run(a: &GroundArgs) -> Result<()> {
    crate::preflight::check_output_files(&[
        (a.common.json.as_deref(), "--json"),
        (a.common.write_scenario.as_deref(), "--write-scenario"),
        (a.plot.as_deref(), "--plot"),
    ])?;
    let input = load_input(&a.common.scenario)?;
    let d = with_bars(a.common.quiet, run_ground_design, &input, &a.options())?;
    // Files first, each attempted; then the tables and what was written.
    let (c, json) = (&a.common, json_text(&d.to_json())?);
    let outcomes = [
        c.write_scenario
            .as_deref()
            .map(|p| (p, write_text(p, &d.design_toml))),
        a.plot.as_deref().map(|p| (p, plot(p, &d))),
        c.json.as_deref().map(|p| (p, write_text(p, &json))),
    ];
    print_ground(&d);
    let mut failures = Vec::new();
    for (path, outcome) in outcomes.into_iter().flatten() {
        match outcome {
            Ok(()) => println!("wrote {}", path.display()),
            Err(e) => failures.push(format!("{e:#}")),
        }
    }
    if !failures.is_empty() {
        return Err(crate::exit_code::Runtime(failures.join("; also: ")).into());
    }
    Ok(d.verdict()?)
}

/// The δ line of a geometry: raw SI and scaled minimum and maximum.
fn print_delta(method: Method, d: &DegreeSeries) {
    let ((rmin, rmax), (smin, smax)) = (delta_range(d, false), delta_range(d, true));
    println!(
        "  delta ({}) raw SI: min {rmin:.4e}, max {rmax:.4e};  scaled: min {smin:.4e}, max \
         {smax:.4e}",
        method.name()
    );
}

/// The problem, the optimum, the scenario's own sites, the paper's range, units and search.
fn print_ground(d: &GroundDesign) {
    let (o, objective) = (&d.options, d.objective);
    println!("scenario    {}", d.scenario);
    let visibility = if d.whole_entry {
        format!(
            "each visible during the whole entry (eq. 52, min elevation {:.3} deg)",
            d.min_elevation_rad.to_degrees()
        )
    } else {
        "each seeing part of the entry".to_string()
    };
    println!(
        "problem     {} ground beacons on the reference sphere, {visibility}, at least {} deg \
         apart, measuring above a {} deg elevation mask (input's sites: {} deg)",
        d.count, o.min_separation_deg, o.elevation_mask_deg, d.own_mask_deg
    );
    println!("objective   {}: {}", objective.name(), objective.units());
    println!(
        "            search on samples every {} s, reported every {} s",
        o.search_step, o.step
    );
    println!();
    let value = fmt_value(d.evaluation.value);
    println!("optimum     {} = {value}", objective.name());
    print_sites(&d.solution.sites, Some(&d.evaluation.min_elevation_rad));
    print_delta(d.method, &d.delta);
    if let Some(b) = &d.bounds {
        print_bound("optimum", b[0]);
        print_bound("input  ", b[1]);
    }
    if let Some((r, delta)) = &d.reference {
        println!();
        println!(
            "scenario's own sites{}: {} = {}",
            if d.is_paper() {
                " (hand-placed like seed 002 Fig. 4)"
            } else {
                ""
            },
            objective.name(),
            fmt_value(r.value)
        );
        print_sites(&d.own, Some(&r.min_elevation_rad));
        print_delta(d.method, delta);
    }
    if d.is_paper() {
        println!();
        println!(
            "paper (seed 002 Sec. 5.1, its optimum): delta from 1.413e-8 to 2.945e-7 along the \
             entry (raw SI)"
        );
    }
    println!();
    println!(
        "units       raw SI delta: states r [m], lon, lat [rad], v [m/s], fpa, heading [rad], \
         outputs [m], Lie order k rows in m/s^k; scaled: {}",
        d.scaling
    );
    if let Some(l) = &d.lincov {
        print_lincov(l);
    }
    print_search(&d.solution.search, d.solution.elapsed_s, d.wall_s, &d.opts);
    print_check(d.check.as_ref());
}

/// The nominal position bound line of a design.
fn print_bound(label: &str, (avg, last): (f64, f64)) {
    println!("  nominal position PCRLB, {label}: {avg:.2} m time-averaged, {last:.2} m final");
}

/// `--plot`: raw δ(t) of the optimum and of the scenario's sites.
fn plot(path: &Path, d: &GroundDesign) -> Result<()> {
    let curve = |name: String, s: &DegreeSeries, dashed: bool| entrynav_render::chart::Curve {
        name,
        points: s.times().into_iter().zip(s.deltas(false)).collect(),
        dashed,
        color: None,
    };
    let mut curves = vec![curve(
        format!("optimum (min {:.3e})", delta_range(&d.delta, false).0),
        &d.delta,
        false,
    )];
    if let Some((_, s)) = &d.reference {
        let name = format!("scenario's sites (min {:.3e})", delta_range(s, false).0);
        curves.push(curve(name, s, true));
    }
    write_text(path, "")?;
    crate::figures::write_line_plot(
        path,
        &format!(
            "{}: raw SI δ = σmin/σmax ({}) along the entry",
            d.scenario,
            d.method.name()
        ),
        "time (s)",
        "δ (raw SI)",
        true,
        &curves,
    )
}
