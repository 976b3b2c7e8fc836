//! `entrynav optimize select --exact`: the branch and bound of
//! `entrynav_optimizer::select::branch_bound` with a progress line (incumbent, bound, open nodes),
//! its summary and its JSON, and the run without a heuristic start.

use super::ground_sites::sites_json;
use super::site_selection::{constraints_json, print_selection, selection_json, write_selected};
use super::*;
use entrynav_optimizer::select::{BranchBoundOptions, BranchBoundProgress};
use std::time::Duration;

/// Run the branch and bound from `start` (the heuristic answer, if any).
pub(super) fn run_exact(
    a: &SelectArgs,
    problem: &SelectionProblem,
    start: Option<&Selection>,
) -> Result<BranchBoundReport> {
    let time_limit = match a.time_limit {
        Some(t) if !(t.is_finite() && t >= 0.0) => bail!("--time-limit {t} must be >= 0 seconds"),
        Some(t) => Some(Duration::from_secs_f64(t)),
        None => None,
    };
    let opts = BranchBoundOptions {
        gap: a.gap,
        time_limit,
        node_limit: a.node_limit,
        batch: a.batch,
        ..BranchBoundOptions::default()
    };
    let bar = if a.quiet {
        ProgressBar::hidden()
    } else {
        ProgressBar::new_spinner()
    };
    bar.set_style(
        ProgressStyle::with_template("{spinner} {msg} [{elapsed}]")
            .unwrap_or_else(|_| ProgressStyle::default_spinner()),
    );
    let progress = |p: &BranchBoundProgress| {
        bar.set_message(format!(
            "branch and bound: {} nodes, {} open, incumbent {:.6}, bound {:.6}, gap {:.2e}",
            p.nodes,
            p.open,
            p.incumbent,
            p.bound,
            p.bound - p.incumbent
        ));
        bar.tick();
    };
    let report = problem.branch_and_bound(&opts, start, &progress)?;
    bar.finish_and_clear();
    Ok(report)
}

/// The summary line of the proof.
pub(super) fn print_proof(a: &SelectArgs, r: &BranchBoundReport) {
    let threads = rayon::current_num_threads();
    println!(
        "proof       {}: certified gap {:.3e} (bound {:.6}; optimal at <= {:.1e}, requested \
         --gap {:.1e}){}",
        r.status.name(),
        r.gap,
        r.bound,
        r.proof_tolerance,
        a.gap,
        match r.status {
            ProofStatus::TimeLimit => format!(
                ", stopped at --time-limit {} s",
                a.time_limit.unwrap_or(0.0)
            ),
            ProofStatus::NodeLimit =>
                format!(", stopped at --node-limit {}", a.node_limit.unwrap_or(0)),
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
        a.batch,
        threads
    );
    if r.solver_trouble > 0 {
        println!(
            "            {} node solve(s) stopped early; their dual bounds are valid all the same",
            r.solver_trouble
        );
    }
}

/// The `exact` object of the JSON report.
pub(super) fn exact_json(a: &SelectArgs, r: &BranchBoundReport, sites: &[Site]) -> Value {
    let chosen: Vec<Site> = r.best.indices.iter().map(|&i| sites[i]).collect();
    json!({
        "status": r.status.name(),
        "value": r.best.value,
        "indices": r.best.indices,
        "sites": sites_json(&chosen),
        "bound": r.bound,
        "gap": r.gap,
        "requested_gap": a.gap,
        "proof_tolerance": r.proof_tolerance,
        "time_limit_s": a.time_limit,
        "node_limit": a.node_limit,
        "root_bound": r.root_bound,
        "initial_value": r.initial_value,
        "nodes": r.nodes,
        "solver_calls": r.solver_calls,
        "solver_trouble": r.solver_trouble,
        "pruned_cheap": r.pruned_cheap,
        "pruned_relaxation": r.pruned_relaxation,
        "pruned_queued": r.pruned_queued,
        "screened": r.screened,
        "leaves": r.leaves,
        "infeasible": r.infeasible,
        "branched": r.branched,
        "open": r.open,
        "max_depth": r.max_depth,
        "incumbent_updates": r.incumbent_updates,
        "batch": a.batch,
        "threads": rayon::current_num_threads(),
        "elapsed_s": r.elapsed_s,
    })
}

/// `--exact` when the heuristic failed: the branch and bound alone, its summary, JSON and
/// scenario file.
pub(super) fn finish_exact_only(
    a: &SelectArgs,
    cfg: &ScenarioConfig,
    problem: &SelectionProblem,
    sites: &[Site],
    grid_count: usize,
    wall: Instant,
) -> Result<()> {
    let e = run_exact(a, problem, None)?;
    let brute = problem.brute_force(a.brute_force_limit);
    let show = |label: &str, s: &Selection| print_selection(label, s, sites, e.bound, problem);
    if let Some(b) = &brute {
        show("brute force (exact optimum)", b);
    }
    show("branch and bound (answer)", &e.best);
    print_proof(a, &e);
    write_selected(
        a,
        cfg,
        sites,
        problem.criterion(),
        &e.best,
        e.bound,
        Some(&e),
    )?;
    if let Some(path) = &a.json {
        let chosen: Vec<Site> = e.best.indices.iter().map(|&i| sites[i]).collect();
        write_json(
            path,
            &json!({
                "problem": "select",
                "scenario": cfg.name,
                "objective": problem.criterion().name(),
                "answer": "exact",
                "value": e.best.value,
                "sites": sites_json(&chosen),
                "bound": e.bound,
                "gap": e.gap,
                "k": a.k,
                "candidates": sites.len(),
                "grid_candidates": grid_count,
                "grid_deg": a.grid_deg,
                "wall_s": wall.elapsed().as_secs_f64(),
                "constraints": constraints_json(a, problem.constraints().len()),
                "brute_force": brute.as_ref().map(|b| selection_json(b, sites, e.bound)),
                "exact": exact_json(a, &e, sites),
            }),
        )?;
    }
    Ok(())
}
