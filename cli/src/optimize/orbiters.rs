//! `entrynav optimize orbiters`: the orbiter design (`entrynav_studies::design::orbiters`), its
//! tables, the trajectory CSV, the scenario with the optimized orbiters, the plot of the
//! integrand and the JSON, and exit code 1 when the check finds the optimum worse.

use super::args::OrbitersArgs;
use super::files::{json_text, load_input, tell, write_text};
use super::progress_bars::with_bars;
use super::tables::{print_check, print_elements, print_lincov, print_search};
use anyhow::Result;
use entrynav_optimizer::{OrbiterBoundSolution, OrbiterProblem};
use entrynav_studies::design::orbiters_result::{OrbiterDesign, PAPER_VALUE};
use entrynav_studies::design::run_orbiter_design;

/// Run the command.
pub fn run(a: &OrbitersArgs) -> Result<()> {
    crate::preflight::check_output_files(&[
        (a.common.json.as_deref(), "--json"),
        (a.common.write_scenario.as_deref(), "--write-scenario"),
        (a.plot.as_deref(), "--plot"),
        (a.export_trajectory.as_deref(), "--export-trajectory"),
    ])?;
    let (c, input) = (&a.common, load_input(&a.common.scenario)?);
    let d = with_bars(c.quiet, run_orbiter_design, &input, &a.options())?;
    print_orbiters(&d);
    print_check(d.check.as_ref());
    let (csv, toml, json) = (d.trajectory_csv(), &d.design_toml, json_text(&d.to_json())?);
    tell(a.export_trajectory.as_deref(), |p| write_text(p, &csv))?;
    tell(c.write_scenario.as_deref(), |p| write_text(p, toml))?;
    tell(a.plot.as_deref(), |p| plot(p, &d))?;
    tell(c.json.as_deref(), |p| write_text(p, &json))?;
    Ok(d.verdict()?)
}

/// The problem, the optimum, the scenario's own orbiters, the search and the PCRLB polish.
fn print_orbiters(d: &OrbiterDesign) {
    let (problem, sol) = (&d.problem, &d.sol);
    let (traj, ev) = (problem.trajectory(), &sol.evaluation);
    println!("scenario    {}", d.scenario);
    println!(
        "problem     {} orbiters on circular orbits at {:.1} km (seed 002 eq. 55-56), line of \
         sight by eq. 58-60",
        d.count,
        d.altitude_m / 1e3
    );
    println!(
        "objective   {} = integral over t of {} (trapezoid over {} samples, {:.0} s; upper bound \
         {:.3})",
        problem.objective().name(),
        d.integrand().0,
        traj.len(),
        traj.duration(),
        problem.upper_bound()
    );
    println!();
    println!("optimum     {:.3}", ev.value);
    print_elements(&sol.elements);
    println!(
        "  min visibility margin {:.3} deg, {:.1} % of orbiter-epochs in view",
        ev.min_margin_rad.to_degrees(),
        100.0 * ev.visible_fraction
    );
    if let Some((el, r)) = &d.reference {
        println!();
        let paper = format!(" (seed 002 Table 6; paper reports {PAPER_VALUE})");
        println!(
            "scenario's own orbiters{} evaluated by the same objective: {:.3}",
            if d.is_paper() { paper.as_str() } else { "" },
            r.value
        );
        print_elements(el);
        let margin = r.min_margin_rad.to_degrees();
        println!("  min visibility margin {margin:.3} deg");
    }
    println!();
    print_search(&sol.search, sol.elapsed_s, d.wall_s, &d.opts);
    if let Some(b) = &d.bound {
        print_bound_polish(problem, b, d.own_bound);
    }
    if let Some(n) = &d.nav {
        println!();
        println!(
            "bound       objective {} on the nominal position PCRLB (full global search); the \
             geometric value above is reported for comparison",
            n.objective
        );
        println!(
            "optimum     {:.2} m time-averaged, {:.2} m final{}",
            n.solution.series.time_avg(),
            n.solution.series.final_value(),
            n.own.map_or(String::new(), |(a, f)| format!(
                "  (scenario's own orbiters: {a:.2} m, {f:.2} m)"
            ))
        );
        if let Some(l) = &n.lincov {
            print_lincov(l);
        }
    }
}

/// The `pcrlb` lines: the polished bound against the geometric optimum's and the scenario's.
fn print_bound_polish(problem: &OrbiterProblem, b: &OrbiterBoundSolution, own_bound: Option<f64>) {
    let name = problem.objective().name();
    println!();
    println!(
        "pcrlb       final position PCRLB of the scenario with these orbiters (IMU, dynamics, \
         prior and ranges; run 0 of seed 1), polished from the {name} optimum"
    );
    println!(
        "optimum     {:.3} m  (at the {name} optimum {:.3} m{})",
        b.bound_m,
        b.proxy_bound_m,
        own_bound.map_or(String::new(), |v| format!(
            "; scenario's own orbiters {v:.3} m"
        ))
    );
    print_elements(&b.elements);
    println!(
        "  polish: {} bound evaluations, {:.1} s (proxy search and polish)",
        b.search.evaluations, b.elapsed_s
    );
}

/// `--plot`: the integrand along the entry, optimum against the scenario's orbiters.
fn plot(path: &std::path::Path, d: &OrbiterDesign) -> Result<()> {
    let problem = &d.problem;
    let ev = &d.sol.evaluation;
    let t = &problem.trajectory().times;
    let curve = |name: String, integrand: &[f64], dashed: bool| entrynav_render::chart::Curve {
        name,
        points: t.iter().copied().zip(integrand.iter().copied()).collect(),
        dashed,
        color: None,
    };
    let mut curves = vec![curve(
        format!("optimum ({:.3})", ev.value),
        &ev.integrand,
        false,
    )];
    if let Some((_, r)) = &d.reference {
        let name = format!("scenario's orbiters ({:.3})", r.value);
        curves.push(curve(name, &r.integrand, true));
    }
    write_text(path, "")?;
    let title = format!(
        "{}: {} integrand along the entry",
        d.scenario,
        problem.objective().name()
    );
    crate::figures::write_line_plot(path, &title, "time (s)", d.integrand().1, false, &curves)
}
