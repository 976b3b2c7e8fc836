//! The JSON `entrynav optimize select --json` writes, for each way the selection was answered.

use crate::design::check::DesignCheck;
use crate::design::choices::Choice;
use crate::design::lincov_stage::figures_json;
use crate::design::select_options::SelectOptions;
use crate::design::select_result::{Certified, ExactOnly, OnBound, SelectionAnswer, SiteSelection};
use crate::design::sites::{chosen, sites_json};
use entrynav_optimizer::{BranchBoundReport, Selection, Site};
use serde_json::{Value, json};

/// `value` and `gap = bound − value` of a selection (`bound`: the best bound known).
fn selection_json(s: &Selection, sites: &[Site], bound: f64) -> Value {
    json!({
        "indices": s.indices,
        "sites": sites_json(&chosen(sites, &s.indices)),
        "value": s.value,
        "gap": (bound - s.value).max(0.0),
    })
}

/// The side constraints: minimum separation (with the number of closer pairs) and region.
fn constraints_json(o: &SelectOptions, pairs: usize) -> Value {
    json!({
        "min_separation_deg": (o.min_separation_deg > 0.0).then_some(o.min_separation_deg),
        "close_pairs": pairs,
        "region_deg": o.region,
    })
}

impl SiteSelection {
    /// The JSON `entrynav optimize select --json` writes.
    pub fn to_json(&self) -> Value {
        match &self.answer {
            SelectionAnswer::Certified(c) => self.certified_json(c),
            SelectionAnswer::ExactOnly(e) => self.exact_only_json(e),
            SelectionAnswer::OnBound(b) => self.on_bound_json(b),
        }
    }

    /// The `exact` object: the proof and the work it took.
    fn exact_json(&self, r: &BranchBoundReport) -> Value {
        let o = &self.options;
        json!({
            "status": r.status.name(),
            "value": r.best.value,
            "indices": r.best.indices,
            "sites": sites_json(&chosen(&self.candidates.sites, &r.best.indices)),
            "bound": r.bound,
            "gap": r.gap,
            "requested_gap": o.gap,
            "proof_tolerance": r.proof_tolerance,
            "time_limit_s": o.time_limit,
            "node_limit": o.node_limit,
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
            "batch": o.batch,
            "threads": self.threads,
            "elapsed_s": r.elapsed_s,
        })
    }

    /// The answer, the relaxation and its support, every selection and the proof.
    fn certified_json(&self, c: &Certified) -> Value {
        let (o, sites) = (&self.options, &self.candidates.sites);
        let (report, r) = (&c.report, &c.report.relaxation);
        let (answer, bound) = (c.answer(), c.bound());
        let support: Vec<Value> =
            r.z.iter()
                .enumerate()
                .filter(|(_, z)| **z > 1e-4)
                .map(|(i, z)| {
                    let [lat, lon] = sites[i].degrees();
                    json!({"index": i, "z": z, "lat_deg": lat, "lon_deg": lon})
                })
                .collect();
        json!({
            "problem": "select",
            "scenario": self.scenario,
            "objective": c.problem.criterion().name(),
            "eig_epochs_s": o.eig_epochs,
            "answer": if c.exact.is_some() { "exact" } else { "heuristic" },
            "value": answer.value,
            "sites": sites_json(&self.sites()),
            "bound": bound,
            "gap": (bound - answer.value).max(0.0),
            "k": o.k,
            "candidates": sites.len(),
            "grid_candidates": self.candidates.grid_count,
            "grid_deg": o.grid_deg,
            "evaluations": report.evaluations,
            "elapsed_s": report.elapsed_s,
            "wall_s": self.wall_s,
            "relaxation": {
                "status": r.status.to_string(),
                "iterations": r.iterations,
                "primal": r.primal,
                "dual": r.dual,
                "solve_time_s": r.solve_time_s,
                "support": support,
            },
            "rounded": report.rounded.as_ref().map(|s| selection_json(s, sites, bound)),
            "greedy": report.greedy.as_ref().map(|s| selection_json(s, sites, bound)),
            "heuristic": selection_json(&report.improved, sites, bound),
            "brute_force": c.brute.as_ref().map(|b| selection_json(b, sites, bound)),
            "certified": c.certified.iter().map(|(label, s)| {
                let mut v = selection_json(s, sites, bound);
                v["label"] = json!(label);
                v["admissible"] = json!(c.problem.admissible(&s.indices));
                v
            }).collect::<Vec<_>>(),
            "constraints": constraints_json(o, c.close_pairs),
            "exact": c.exact.as_ref().map(|e| self.exact_json(e)),
            "check": self.check.as_ref().map(DesignCheck::json),
        })
    }

    /// The branch and bound alone.
    fn exact_only_json(&self, x: &ExactOnly) -> Value {
        let (o, sites, e) = (&self.options, &self.candidates.sites, &x.exact);
        json!({
            "problem": "select",
            "scenario": self.scenario,
            "objective": x.problem.criterion().name(),
            "answer": "exact",
            "value": e.best.value,
            "sites": sites_json(&self.sites()),
            "bound": e.bound,
            "gap": e.gap,
            "k": o.k,
            "candidates": sites.len(),
            "grid_candidates": self.candidates.grid_count,
            "grid_deg": o.grid_deg,
            "wall_s": self.wall_s,
            "constraints": constraints_json(o, x.problem.constraints().len()),
            "brute_force": x.brute.as_ref().map(|b| selection_json(b, sites, e.bound)),
            "exact": self.exact_json(e),
        })
    }

    /// The local search on the nominal bound.
    fn on_bound_json(&self, b: &OnBound) -> Value {
        let (o, sel, bounds) = (&self.options, &b.selection, &b.bounds);
        json!({
            "problem": "select",
            "scenario": self.scenario,
            "objective": b.objective.name(),
            "answer": "local search on the nominal bound (no certificate)",
            "value": sel.value,
            "sites": sites_json(&self.sites()),
            "k": o.k,
            "candidates": self.candidates.sites.len(),
            "grid_candidates": self.candidates.grid_count,
            "grid_deg": o.grid_deg,
            "evaluations": sel.evaluations,
            "exchanges": sel.exchanges,
            "wall_s": self.wall_s,
            "constraints": constraints_json(o, 0),
            "nominal_bound": {
                "optimum": {"time_avg_pos_m": bounds[0].0, "final_pos_m": bounds[0].1},
                "input": {"time_avg_pos_m": bounds[1].0, "final_pos_m": bounds[1].1},
            },
            "check": self.check.as_ref().map(DesignCheck::json),
            "lincov": b.lincov.as_ref().map(|(f, input, l)| json!({
                "objective": b.objective.name(),
                "filter": f.name(),
                "value": l.value,
                "input": input.as_ref().map(figures_json),
                "bound_selection": figures_json(&l.start_figures),
                "optimum": figures_json(&l.figures),
                "evaluations": l.evaluations,
                "exchanges": l.exchanges,
            })),
        })
    }
}
