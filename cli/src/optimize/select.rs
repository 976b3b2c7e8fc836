//! `entrynav optimize select`: the site selection (`entrynav_studies::design::select`), its
//! notes and tables — the relaxation, every selection with its certified gap and the proof; or
//! the local search on the nominal bound — its files, and exit code 1 when the check finds the
//! answer worse.

use super::args::SelectArgs;
use super::files::{json_text, load_input, tell, write_text};
use super::progress_bars::with_bars;
use super::tables::{lincov_figures, print_check, print_sites};
use anyhow::Result;
use entrynav_optimizer::{BranchBoundReport, ProofStatus, Selection};
use entrynav_optimizer::{SelectionProblem, Site};
use entrynav_studies::design::select_result::{Certified, OnBound};
use entrynav_studies::design::{Choice, SelectionAnswer, SiteSelection, run_site_selection};

/// Run the command.
pub fn run(a: &SelectArgs) -> Result<()> {
    crate::preflight::check_output_files(&[
        (a.json.as_deref(), "--json"),
        (a.write_scenario.as_deref(), "--write-scenario"),
    ])?;
    let input = load_input(&a.scenario)?;
    let s = with_bars(a.quiet, run_site_selection, &input, &a.options())?;
    for n in &s.notes {
        println!("note: {n}");
    }
    let (scenario, json) = (a.write_scenario.as_deref(), a.json.as_deref());
    let (json_text, toml) = (json_text(&s.to_json())?, &s.design_toml);
    match &s.answer {
        SelectionAnswer::OnBound(b) => {
            // Files first, then the tables.
            for (path, text) in [(scenario, toml), (json, &json_text)] {
                path.map(|p| write_text(p, text)).transpose()?;
            }
            print_on_bound(&s, b);
            for path in [scenario, json].into_iter().flatten() {
                println!("wrote {}", path.display());
            }
        }
        SelectionAnswer::Certified(c) => {
            print_certified(&s, c);
            print_check(s.check.as_ref());
        }
        SelectionAnswer::ExactOnly(x) => {
            let (sites, e) = (&s.candidates.sites, &x.exact);
            let show = |label: &str, sel: &Selection| {
                print_selection(label, sel, sites, e.bound, &x.problem)
            };
            if let Some(b) = &x.brute {
                show("brute force (exact optimum)", b);
            }
            show("branch and bound (answer)", &e.best);
            print_proof(&s, e);
        }
    }
    if !matches!(s.answer, SelectionAnswer::OnBound(_)) {
        tell(scenario, |p| write_text(p, toml))?;
        tell(json, |p| write_text(p, &json_text))?;
    }
    Ok(s.verdict()?)
}

/// One line per selection: value, gap from `bound` and sites (and whether it breaks the side
/// constraints).
fn print_selection(label: &str, s: &Selection, sites: &[Site], bound: f64, p: &SelectionProblem) {
    let chosen: Vec<String> = s
        .indices
        .iter()
        .map(|&i| {
            let [lat, lon] = sites[i].degrees();
            format!("({lat:.2}, {lon:.2})")
        })
        .collect();
    println!(
        "{label:<30} value {:>11.6}  gap {:>10.3e}  sites {}{}",
        s.value,
        (bound - s.value).max(0.0),
        chosen.join(" "),
        if p.admissible(&s.indices) {
            ""
        } else {
            "  (breaks the side constraints)"
        }
    );
}

/// The candidates, constraints, criterion and relaxation, then every selection and the proof.
fn print_certified(s: &SiteSelection, c: &Certified) {
    let (o, sites, grid_count) = (&s.options, &s.candidates.sites, s.candidates.grid_count);
    println!("scenario    {}", s.scenario);
    println!(
        "candidates  {grid_count} grid sites every {} deg visible during the whole entry (min \
         elevation {} deg){}",
        o.grid_deg,
        o.min_elevation_deg,
        if sites.len() > grid_count {
            format!(" + {} sites to certify", sites.len() - grid_count)
        } else {
            String::new()
        }
    );
    if o.min_separation_deg > 0.0 || o.region.is_some() {
        let d = o.min_separation_deg;
        let pairs = c.close_pairs;
        println!(
            "constraints {}{}",
            if d > 0.0 {
                format!("sites at least {d} deg apart ({pairs} closer pairs, z_i + z_j <= 1); ")
            } else {
                String::new()
            },
            o.region.as_ref().map_or(String::new(), |b| format!(
                "candidates inside lat [{}, {}], lon [{}, {}] deg",
                b[0], b[1], b[2], b[3]
            ))
        );
    }
    let criterion = c.problem.criterion();
    println!(
        "criterion   {} over k = {} of m = {} ({})",
        criterion.name(),
        o.k,
        sites.len(),
        c.criterion_definition(o.eig_epochs)
    );
    let (report, r) = (&c.report, &c.report.relaxation);
    println!(
        "relaxation  bound {:.6} (primal {:.6}, dual {:.6}; clarabel {}, {} iterations, {:.3} s)",
        r.bound, r.primal, r.dual, r.status, r.iterations, r.solve_time_s
    );
    let bound = c.bound();
    let show = |label: &str, sel: &Selection| print_selection(label, sel, sites, bound, &c.problem);
    if let Some(sel) = &report.rounded {
        show("rounded (top-k of z)", sel);
    }
    show(
        if c.exact.is_some() {
            "swap-improved (heuristic)"
        } else {
            "swap-improved (answer)"
        },
        &report.improved,
    );
    if let Some(sel) = &report.greedy {
        show("greedy", sel);
    }
    if let Some(b) = &c.brute {
        show("brute force (exact optimum)", b);
    }
    if let Some(e) = &c.exact {
        show("branch and bound (answer)", &e.best);
    }
    for (label, sel) in &c.certified {
        show(label, sel);
    }
    println!(
        "            {} criterion evaluations, {:.3} s wall",
        report.evaluations, s.wall_s
    );
    if let Some(e) = &c.exact {
        print_proof(s, e);
    }
}

/// The summary lines of the proof.
fn print_proof(s: &SiteSelection, r: &BranchBoundReport) {
    let o = &s.options;
    println!(
        "proof       {}: certified gap {:.3e} (bound {:.6}; optimal at <= {:.1e}, requested \
         --gap {:.1e}){}",
        r.status.name(),
        r.gap,
        r.bound,
        r.proof_tolerance,
        o.gap,
        match r.status {
            ProofStatus::TimeLimit => format!(
                ", stopped at --time-limit {} s",
                o.time_limit.unwrap_or(0.0)
            ),
            ProofStatus::NodeLimit =>
                format!(", stopped at --node-limit {}", o.node_limit.unwrap_or(0)),
            ProofStatus::Optimal | ProofStatus::Gap => String::new(),
        }
    );
    println!(
        "            {} nodes ({} clarabel solves, {} pruned by cheap bounds, {} by relaxation \
         bounds, {} leaves, {} sites screened out), {} open, depth {}, {:.3} s, batch {} on {} \
         thread(s)",
        r.nodes,
        r.solver_calls,
        r.pruned_cheap,
        r.pruned_relaxation,
        r.leaves,
        r.screened,
        r.open,
        r.max_depth,
        r.elapsed_s,
        o.batch,
        s.threads
    );
    if r.solver_trouble > 0 {
        println!(
            "            {} node solve(s) stopped early; their dual bounds are valid all the same",
            r.solver_trouble
        );
    }
}

/// The local search on the nominal bound: the answer, its bound against the input's and the
/// LinCov exchanges.
fn print_on_bound(s: &SiteSelection, b: &OnBound) {
    let (o, sel, name) = (&s.options, &b.selection, b.objective.name());
    println!("scenario    {}", s.scenario);
    println!(
        "candidates  {} grid sites every {} deg visible during the whole entry, k = {}, at least \
         {} deg apart",
        s.candidates.grid_count, o.grid_deg, o.k, o.min_separation_deg
    );
    println!("objective   {name}: {}", b.units());
    println!(
        "search      greedy + exchanges: {} bound evaluations, {} improving exchanges, {:.2} s; a \
         local optimum, no certificate (the bound is not concave in the selection)",
        sel.evaluations, sel.exchanges, s.wall_s
    );
    println!();
    println!("answer      {name} = {:.6}", sel.value);
    print_sites(&s.sites(), None);
    for (label, (avg, last)) in [("answer", b.bounds[0]), ("input ", b.bounds[1])] {
        println!("  nominal position PCRLB, {label}: {avg:.2} m time-averaged, {last:.2} m final");
    }
    if let Some((f, input, l)) = &b.lincov {
        let f = f.name();
        println!(
            "lincov      {} exchanges on LinCov of {f} ({} evaluations): {name}",
            l.exchanges, l.evaluations
        );
        if let Some(i) = input {
            println!(
                "  predicted {f} position RMSE, input:           {}",
                lincov_figures(i)
            );
        }
        let start = lincov_figures(&l.start_figures);
        println!("  predicted {f} position RMSE, bound selection: {start}");
        println!(
            "  predicted {f} position RMSE, answer:          {}",
            lincov_figures(&l.figures)
        );
    }
    print_check(s.check.as_ref());
}
